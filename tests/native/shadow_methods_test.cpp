// The shadow methods (rtsdf, rt_only, jfa_only, csm_evsm, raytraced): the same
// sphere over a ground as RendererTest.SpherePenumbraMatchesAnalyticWidth,
// small and with few samples, against the analytic soft shadow.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <glm/gtc/matrix_transform.hpp>
#include <string>

#include "analytic_shadow.h"
#include "reference/shapes.h"
#include "renderer.h"
#include "top_view.h"
#include "vulkan_test.h"

namespace rtsdf {
namespace {

using testing::top_view;

using testing::Profile;
using testing::profile;
using testing::sphere_visibility;

constexpr float kRadius = 0.5f, kHeight = 1.0f;  // the sphere, centred above the origin
constexpr int kSize = 64;                         // pixels over the 4 x 4 view

// One renderer for the whole file: its pipelines are compiled once.
Renderer& shared_renderer() {
  static Renderer renderer(testing::VulkanTest::context());
  return renderer;
}

Scene sphere_over_ground() {
  Scene scene;
  scene.meshes = {reference::uv_sphere({0, 0, kHeight}, kRadius, 48), reference::sheet({-20, -20}, {20, 20}, 0.0f)};
  scene.instances = {{0, glm::mat4(1.0f), glm::vec3(0.8f)}, {1, glm::mat4(1.0f), glm::vec3(0.8f)}};
  return scene;
}

// Settings small enough for a test: coarser grids, few samples.
RenderSettings small_settings(ShadowMethod method) {
  RenderSettings settings;
  settings.shadow_method = method;
  settings.coarse_resolution = 32;
  settings.fine_resolution = 64;
  settings.samples = method == ShadowMethod::CsmJitter ? 16 : 3;  // (its penumbra is the frames' mean)
  settings.shadow_map_size = 512;
  return settings;
}

// The shadow pass along the row through y = 0: pixel i covers x = -2 + (i + 0.5) * 4 / size.
struct Row {
  const RenderOutput& out;
  double operator()(double x) const { return at(x, 0.0); }
  double at(double x, double y) const {  // (rows top to bottom: +y first)
    int i = std::clamp(int((x + 2.0) / 4.0 * kSize), 0, kSize - 1);
    int j = std::clamp(int((2.0 - y) / 4.0 * kSize), 0, kSize - 1);
    return double(out.shadow[size_t(j) * kSize + i]);
  }
  double mean(double from, double to) const {
    double sum = 0.0;
    int n = 0;
    for (double x = from; x <= to; x += 4.0 / kSize) sum += (*this)(x), ++n;
    return sum / n;
  }
};

// The size of the unit the method's shadow edge is quantized to: a voxel of
// the field it marches, or a texel of the shadow map.
double method_unit(ShadowMethod method, const GpuScene& scene, const RenderSettings& settings,
                   const Renderer& renderer) {
  const GridSpec coarse = fit_grid(scene.bounds(), settings.coarse_resolution);
  switch (method) {
    case ShadowMethod::Rtsdf:
    case ShadowMethod::RtOnly:
      return FineSdf::fit(coarse, settings.fine_resolution).voxel_size;
    case ShadowMethod::JfaOnly:
      return coarse.voxel_size;
    case ShadowMethod::RayTraced:
      return 4.0 / kSize;  // (exact up to its noise: a pixel)
    case ShadowMethod::CsmEvsm:
    case ShadowMethod::CsmJitter:
      break;
  }
  double texel = 0.0;
  for (const gpu::ShadowTile& tile : renderer.shadow_maps()->tile_data())
    texel = std::max(texel, double(tile.depth_range.z + tile.depth_range.w * 4.0f));  // (a view depth of 4 at most here)
  return texel;
}

// A 10 degree sun at 45 degrees, shining towards +x.
constexpr double kTilt = M_PI / 4, kSunAngle = 10.0 * M_PI / 180.0;
Light tilted_sun() {
  Light sun;
  sun.type = LightType::Sun;
  sun.direction = {float(std::sin(kTilt)), 0, -float(std::cos(kTilt))};
  sun.energy = 3.0f;
  sun.sun_angle = float(kSunAngle);
  return sun;
}

class ShadowMethodsTest : public testing::VulkanTest, public ::testing::WithParamInterface<const char*> {};
class ShadowMapsTest : public testing::VulkanTest {};
class RtOnlyTest : public testing::VulkanTest {};
class RayTracedTest : public testing::VulkanTest {};
class ExactRaysTest : public testing::VulkanTest {};

// tilted_sun(): the shadow's centre is at x = 1, its far edge (half the sun
// hidden) near x = 1.69.
TEST_P(ShadowMethodsTest, SphereShadowUnderSun) {
  const ShadowMethod method = parse_shadow_method(GetParam());
  GpuScene scene(context(), sphere_over_ground());
  const Light sun = tilted_sun();
  const RenderSettings settings = small_settings(method);
  Renderer& renderer = shared_renderer();
  const RenderOutput out = renderer.render(scene, top_view(), {sun}, glm::vec3(0.05f), kSize, kSize, settings);
  ASSERT_EQ(out.shadow.size(), size_t(kSize * kSize));

  const Row rendered{out};
  auto exact = [&](double x) {
    return sphere_visibility({x, 0, 0}, {-std::sin(kTilt), 0, std::cos(kTilt)}, 0.5 * kSunAngle, {0, 0, kHeight},
                             kRadius);
  };
  const Profile r = profile(rendered, 1.0, 4.0 / kSize, 2.0), e = profile(exact, 1.0, 0.001, 2.0);
  const double unit = method_unit(method, scene, settings, renderer), pixel = 4.0 / kSize;
  const double beside = std::min(rendered.at(1.0, 1.5), rendered.at(1.0, -1.5));
  std::printf("%s: umbra %.3f, lit %.3f / %.3f / %.3f; 50%% at %.3f vs %.3f (unit %.4f); 10-90%% %.3f vs %.3f; "
              "%.0f ms (coarse %.0f, fine %.0f, maps %.0f, shade %.0f)\n",
              GetParam(), rendered(1.0), rendered.mean(-1.9, -0.9), beside, rendered(1.97), r.x50, e.x50, unit,
              r.width(), e.width(), out.timings.total_ms, out.timings.coarse_ms, out.timings.fine_ms,
              out.timings.shadow_map_ms, out.timings.shade_ms);
  EXPECT_LT(rendered(1.0), 0.15) << "umbra at the shadow's centre";
  EXPECT_GT(rendered.mean(-1.9, -0.9), 0.95) << "lit on the sun's side of the sphere";
  // (Not right past the far edge: jfa_only's penumbra reaches further out, by
  // the thickness of the coarse field's shell.)
  EXPECT_GT(beside, 0.95) << "lit a unit to either side of the shadow";
  EXPECT_NEAR(r.x50, e.x50, 3.0 * unit + pixel) << "the shadow's edge (half the sun hidden) within 3 voxels or texels";
  // jfa_only and the shadow maps trace no rays: no BVH is built for them.
  // (raytraced and rtsdf_world are not listed: this file keeps to one per kind)
  if (method == ShadowMethod::JfaOnly || method == ShadowMethod::CsmEvsm || method == ShadowMethod::CsmJitter)
    EXPECT_EQ(scene.bvh_build_ms(), 0.0) << "no BVH built";
}

// Meshes as they come: one box turned inside out, one with every other
// triangle flipped, one with every face twice, one with zero-area triangles
// (a repeated corner, three corners on a line), and two boxes through each
// other in one mesh; each hangs over the ground under tilted_sun(), whose
// shadow centre is 0.7 along +x from the box's. Every method renders them
// without NaN, and each casts its umbra (rtsdf with and without exact rays).
TEST_P(ShadowMethodsTest, MessyMeshesCastShadowsWithoutNaN) {
  const ShadowMethod method = parse_shadow_method(GetParam());
  const float ys[5] = {-1.6f, -0.8f, 0.0f, 0.8f, 1.6f};
  auto part = [&](int i) { return reference::box({-0.2f, ys[i] - 0.2f, 0.5f}, {0.2f, ys[i] + 0.2f, 0.9f}); };
  Mesh messy = reference::inside_out(part(0));
  Mesh mixed = part(1);
  for (size_t t = 0; t < mixed.indices.size(); t += 6) std::swap(mixed.indices[t + 1], mixed.indices[t + 2]);
  reference::append(messy, mixed);
  reference::append(messy, part(2));
  reference::append(messy, part(2));  // (every face twice)
  Mesh degenerate = part(3);
  const uint32_t corner = degenerate.indices[0];
  degenerate.positions.push_back({-0.2f, ys[3], 0.9f});  // on a line with the top's corners
  degenerate.positions.push_back({0.2f, ys[3], 0.9f});
  degenerate.positions.push_back({0.0f, ys[3], 0.9f});
  const uint32_t n = uint32_t(degenerate.positions.size());
  degenerate.indices.insert(degenerate.indices.end(), {corner, corner, degenerate.indices[1], n - 3, n - 1, n - 2});
  reference::append(messy, degenerate);
  reference::append(messy, part(4));
  reference::append(messy, reference::box({-0.3f, ys[4] - 0.05f, 0.65f}, {0.3f, ys[4] + 0.05f, 0.75f}));  // (through it)
  Scene scene;
  scene.meshes = {messy, reference::sheet({-20, -20}, {20, 20}, 0.0f)};
  scene.instances = {{0, glm::mat4(1.0f), glm::vec3(0.8f)}, {1, glm::mat4(1.0f), glm::vec3(0.8f)}};
  GpuScene gpu_scene(context(), scene);
  for (int exact_rays : {0, 4}) {
    if (exact_rays > 0 && method != ShadowMethod::Rtsdf) continue;
    RenderSettings settings = small_settings(method);
    settings.exact_rays = exact_rays;
    const RenderOutput out =
        shared_renderer().render(gpu_scene, top_view(), {tilted_sun()}, glm::vec3(0.05f), kSize, kSize, settings);
    size_t non_finite = 0;
    for (float v : out.combined) non_finite += !std::isfinite(v);
    for (float v : out.shadow) non_finite += !std::isfinite(v);
    EXPECT_EQ(non_finite, 0u) << "exact rays " << exact_rays;
    const Row rendered{out};
    for (int i = 0; i < 5; ++i)
      EXPECT_LT(rendered.at(0.7, ys[i]), 0.2) << "umbra of part " << i << ", exact rays " << exact_rays;
  }
}

INSTANTIATE_TEST_SUITE_P(AllMethods, ShadowMethodsTest, ::testing::Values("rtsdf", "rt_only", "jfa_only", "csm_evsm", "csm_jitter", "raytraced"),
                         [](const ::testing::TestParamInfo<const char*>& info) { return std::string(info.param); });

// A shadow-map method with a light of radius 0.15 up and to the -x side of
// the sphere: along y = 0 the shadow's far edge (half the light hidden) is
// near x = 1.23. A spot aimed past the sphere at the ground gets one
// perspective view, a point light a cube of six.
void check_local_light_shadow(ShadowMethod method, LightType type, size_t tiles) {
  GpuScene scene(testing::VulkanTest::context(), sphere_over_ground());
  Light light;
  light.type = type;
  light.position = {-1.0f, 0.0f, 3.5f};
  light.direction = glm::vec3(0.4f, 0.0f, 0.0f) - light.position;
  light.energy = 500.0f;
  light.radius = 0.15f;
  light.spot_size = float(M_PI / 2);
  light.spot_blend = 0.1f;
  const RenderSettings settings = small_settings(method);
  Renderer& renderer = shared_renderer();
  const RenderOutput out = renderer.render(scene, top_view(), {light}, glm::vec3(0.05f), kSize, kSize, settings);
  ASSERT_EQ(renderer.shadow_maps()->tile_data().size(), tiles);

  const Row rendered{out};
  const glm::dvec3 position(light.position);
  auto exact = [&](double x) {
    const glm::dvec3 point(x, 0, 0);
    const double distance = glm::length(position - point);
    return sphere_visibility(point, (position - point) / distance, std::asin(light.radius / distance),
                             {0, 0, kHeight}, kRadius);
  };
  const Profile r = profile(rendered, 0.85, 4.0 / kSize), e = profile(exact, 0.85, 0.001);
  const double unit = method_unit(method, scene, settings, renderer), pixel = 4.0 / kSize;
  std::printf("%s, %zu tile(s): umbra %.3f, lit %.3f / %.3f; 50%% at %.3f vs %.3f (texel %.4f); "
              "10-90%% %.3f vs %.3f\n", shadow_method_name(method), tiles, rendered(0.85), rendered.mean(-1.9, -1.2), rendered.mean(1.6, 1.9),
              r.x50, e.x50, unit, r.width(), e.width());
  EXPECT_LT(rendered(0.85), 0.15) << "umbra";
  EXPECT_GT(rendered.mean(-1.9, -1.2), 0.95) << "lit between the light and the sphere";
  EXPECT_GT(rendered.mean(1.6, 1.9), 0.95) << "lit beyond the shadow";
  EXPECT_NEAR(r.x50, e.x50, 3.0 * unit + pixel) << "the shadow's edge within 3 texels";
}

TEST_F(ShadowMapsTest, SphereShadowUnderSpot) { check_local_light_shadow(ShadowMethod::CsmEvsm, LightType::Spot, 1); }
TEST_F(ShadowMapsTest, SphereShadowUnderPointLightCube) {
  check_local_light_shadow(ShadowMethod::CsmEvsm, LightType::Point, 6);
}
TEST_F(ShadowMapsTest, JitteredSphereShadowUnderSpot) {
  check_local_light_shadow(ShadowMethod::CsmJitter, LightType::Spot, 1);
}
TEST_F(ShadowMapsTest, JitteredSphereShadowUnderPointLightCube) {
  check_local_light_shadow(ShadowMethod::CsmJitter, LightType::Point, 6);
}

// raytraced with 256 samples, and rtsdf with 4 exact rays a frame over 64
// (where its field is not sure: the whole penumbra here): the sun's and a
// spherical light's soft shadows along y = 0 are the analytic ones up to the
// noise of 256 rays a pixel (standard deviation at most 0.5 / 16 = 0.031;
// pixels are 1/16 wide, and the profile is sampled at their centres), on the
// ground beside the sphere. Here no field or map quantizes anything: what is
// left of any method's error against it is its visibility; for the hybrid,
// a pixel its field calls lit or shadowed wrongly would stand out by far more.
void check_converges_to_analytic(ShadowMethod method, int samples, int exact_rays) {
  GpuScene scene(testing::VulkanTest::context(), sphere_over_ground());
  RenderSettings settings = small_settings(method);
  settings.samples = samples;
  settings.exact_rays = exact_rays;
  const Light sun = tilted_sun();
  Light point;
  point.type = LightType::Point;
  point.position = {-1.0f, 0.0f, 3.5f};
  point.energy = 500.0f;
  point.radius = 0.15f;
  const glm::dvec3 centre(0, 0, kHeight);
  for (const Light& light : {sun, point}) {
    const RenderOutput out =
        shared_renderer().render(scene, top_view(), {light}, glm::vec3(0.0f), kSize, kSize, settings);
    const Row rendered{out};
    double worst = 0.0, worst_x = 0.0;
    for (int i = 0; i < kSize; ++i) {
      const double x = -2.0 + (i + 0.5) * 4.0 / kSize;
      if (std::abs(x) < kRadius + 0.05) continue;  // (the camera sees the sphere there, not the ground)
      const glm::dvec3 p(x, 0, 0);
      double exact;
      if (light.type == LightType::Sun) {
        exact = sphere_visibility(p, {-std::sin(kTilt), 0, std::cos(kTilt)}, 0.5 * kSunAngle, centre, kRadius);
      } else {
        const glm::dvec3 to_light = glm::dvec3(light.position) - p;
        const double distance = glm::length(to_light);
        exact = sphere_visibility(p, to_light / distance, std::asin(light.radius / distance), centre, kRadius);
      }
      if (std::abs(rendered(x) - exact) > worst) worst = std::abs(rendered(x) - exact), worst_x = x;
    }
    std::printf("%s (exact rays %d), %s: largest |rendered - exact| along y = 0: %.3f at x = %.3f\n",
                shadow_method_name(method), exact_rays, light.type == LightType::Sun ? "sun" : "point light", worst,
                worst_x);
    EXPECT_LT(worst, 0.13) << "four standard deviations of 256 rays";
  }
}

TEST_F(RayTracedTest, SoftShadowsConvergeToTheAnalyticOnes) { check_converges_to_analytic(ShadowMethod::RayTraced, 256, 0); }
TEST_F(ExactRaysTest, SoftShadowsConvergeToTheAnalyticOnes) { check_converges_to_analytic(ShadowMethod::Rtsdf, 64, 4); }
// csm_jitter's frames each see the light from one point of it: their mean is
// the soft shadow, up to the map's texels (a fifth of a pixel here).
TEST_F(ShadowMapsTest, JitteredMapsConvergeToTheAnalyticSoftShadows) {
  check_converges_to_analytic(ShadowMethod::CsmJitter, 64, 0);
}

// Leaf cards: a tilted row of small open quads over the ground, lit by a
// low sun. A card's field is a slab a voxel thick whichever way it is turned,
// too thin for the cone march to tell how much of the sun it hides (pale
// shadows on a tree's crown); with exact rays where the field is unsure,
// rtsdf's shadow is raytraced's, up to their noise (of the rays, and of the
// edge pixels' coverage by the frames' sub-pixel jitter: 64 frames or more).
TEST_F(ExactRaysTest, LeafCardShadowsAreTheRayTracedOnes) {
  Scene scene;
  scene.meshes.push_back(reference::sheet({-20, -20}, {20, 20}, 0.0f));
  scene.instances.push_back({0, glm::mat4(1.0f), glm::vec3(0.8f)});
  for (int i = 0; i < 6; ++i) {
    scene.meshes.push_back(reference::sheet({-0.12f, -0.12f}, {0.12f, 0.12f}, 0.0f));
    const glm::mat4 place = glm::translate(glm::mat4(1.0f), glm::vec3(-1.2f + 0.4f * i, 0.3f * (i % 3) - 0.3f, 0.6f));
    const glm::mat4 turn = glm::rotate(glm::mat4(1.0f), 0.35f * float(i), glm::normalize(glm::vec3(1, 1, 0)));
    scene.instances.push_back({uint32_t(i + 1), place * turn, glm::vec3(0.8f)});
  }
  GpuScene gpu_scene(context(), scene);
  Light sun = tilted_sun();
  sun.sun_angle = float(2.0 * M_PI / 180.0);
  auto render = [&](ShadowMethod method, int samples, int exact_rays) {
    RenderSettings settings = small_settings(method);
    settings.samples = samples;
    settings.exact_rays = exact_rays;
    return shared_renderer().render(gpu_scene, top_view(), {sun}, glm::vec3(0.0f), kSize, kSize, settings).shadow;
  };
  const std::vector<float> exact = render(ShadowMethod::RayTraced, 256, 0);
  auto error = [&](const std::vector<float>& shadow) {  // mean |shadow - exact| where exact shows a shadow
    double sum = 0.0;
    int count = 0;
    for (size_t i = 0; i < exact.size(); ++i)
      if (exact[i] < 0.9f) sum += std::abs(shadow[i] - exact[i]), ++count;
    EXPECT_GT(count, 40) << "the cards cast shadows in view";
    return sum / std::max(count, 1);
  };
  const double cone = error(render(ShadowMethod::Rtsdf, 64, 0)), hybrid = error(render(ShadowMethod::Rtsdf, 64, 4));
  std::printf("leaf cards: mean |visibility - raytraced's| in their shadows: cone march %.3f, exact rays %.3f\n", cone,
              hybrid);
  EXPECT_LT(hybrid, 0.03) << "exact rays where the field is unsure";
}

// Thin slats a centimetre above a large slab (IvyGen's stems over their
// wall): the slab's march starts half a voxel of its own field along the
// ray and is jittered by up to a voxel more, 12 cm at this size, so the
// slats lie wholly where it does not look. Where another mesh's surface
// is that near the receiver, exact rays decide; before, their shadows on the
// slab were missing (every pixel in them lit).
TEST_F(ExactRaysTest, ThinCastersNearALargeReceiverCastTheirShadows) {
  Scene scene;
  scene.meshes.push_back(reference::box({-4, -4, -0.4f}, {4, 4, 0}));
  Mesh slats;
  for (int i = 0; i < 5; ++i) {
    const float x = -0.3f + 0.12f * float(i);
    reference::append(slats, reference::box({x, -0.5f, 0.01f}, {x + 0.02f, 0.5f, 0.013f}));
  }
  scene.meshes.push_back(slats);
  scene.instances = {{0, glm::mat4(1.0f), glm::vec3(0.8f)}, {1, glm::mat4(1.0f), glm::vec3(0.8f)}};
  GpuScene gpu_scene(context(), scene);
  Light sun;
  sun.type = LightType::Sun;
  sun.direction = glm::normalize(glm::vec3(-2.0f, 0.0f, -1.0f));  // (each slat's shadow 2-2.6 cm beside it)
  sun.energy = 3.0f;
  sun.sun_angle = 0.005f;
  Camera camera;  // (straight down over the slats, 0.7 m across)
  camera.world_to_view = glm::lookAt(glm::vec3(-0.05f, 0, 10), glm::vec3(-0.05f, 0, 0), glm::vec3(0, 1, 0));
  camera.projection = glm::orthoRH_NO(-0.35f, 0.35f, -0.35f, 0.35f, 0.1f, 20.0f);
  camera.orthographic = true;
  auto lit_share = [&](ShadowMethod method, int exact_rays) {
    RenderSettings settings = small_settings(method);
    settings.samples = 16;
    settings.exact_rays = exact_rays;
    const RenderOutput out = shared_renderer().render(gpu_scene, camera, {sun}, glm::vec3(0.0f), 96, 96, settings);
    double lit = 0.0;
    for (float v : out.shadow) lit += v;
    return lit / double(out.shadow.size());
  };
  const double exact = lit_share(ShadowMethod::RayTraced, 0), hybrid = lit_share(ShadowMethod::Rtsdf, 4);
  std::printf("slats over a slab: lit share %.3f with exact rays where unsure, %.3f raytraced\n", hybrid, exact);
  EXPECT_LT(exact, 0.95) << "the slats' shadows are in view";
  EXPECT_NEAR(hybrid, exact, 0.02);
}

// rt_only's fine SDF: every texel of the grid is listed each frame (no band,
// no interleave), where rtsdf lists only the band.
TEST_F(RtOnlyTest, TracesEveryTexelEveryFrame) {
  GpuScene scene(context(), single_mesh_scene(reference::uv_sphere({0, 0, 0}, 1.0f, 24)));
  CoarseSdf coarse(context());
  coarse.build(scene, fit_grid(scene.bounds(), 16), 0.5f);
  const GridSpec grid = FineSdf::fit(coarse.grid(), 32);
  FineTraceSettings band, everywhere;
  band.rays_per_texel = everywhere.rays_per_texel = 2;  // (what is listed is the point here)
  everywhere.trace_everywhere = true;
  everywhere.interleave = 4;  // (ignored)
  FineSdf fine(context());
  fine.update(scene, coarse, grid, band);
  const uint32_t band_texels = fine.read_traced_texels();
  fine.reset();
  for (int frame = 0; frame < 2; ++frame) {
    fine.update(scene, coarse, grid, everywhere);
    EXPECT_EQ(fine.read_traced_texels(), grid.voxel_count()) << "frame " << frame;
  }
  EXPECT_LT(band_texels, grid.voxel_count()) << "rtsdf traces a band only";
}

TEST(ShadowMethodNames, ParseAndNameRoundTripAndUnknownNamesAreErrors) {
  for (const char* name : {"rtsdf", "rtsdf_world", "rt_only", "jfa_only", "csm_evsm", "csm_jitter", "raytraced"})
    EXPECT_STREQ(shadow_method_name(parse_shadow_method(name)), name);
  EXPECT_EQ(RenderSettings{}.shadow_method, ShadowMethod::Rtsdf);
  try {
    parse_shadow_method("pcss");
    ADD_FAILURE() << "no error for an unknown method";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'pcss'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("csm_evsm"), std::string::npos) << "lists the known names: " << e.what();
  }
}

}  // namespace
}  // namespace rtsdf
