// The renderer: a sphere over a plane under a sun, seen from above, against
// the analytic soft shadow (the visible share of the sun's disk).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <glm/gtc/matrix_transform.hpp>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include "analytic_shadow.h"
#include "exr_output.h"
#include "reference/shapes.h"
#include "renderer.h"
#include "vulkan_test.h"

namespace rtsdf {
namespace {

using testing::hidden_share;
using testing::Profile;
using testing::profile;

class RendererTest : public testing::VulkanTest {};

// An orthographic camera at `eye` looking at `target`, seeing `half_size` world units to each side.
Camera orthographic_view(glm::vec3 eye, glm::vec3 target, glm::vec3 up, float half_size) {
  Camera camera;
  camera.world_to_view = glm::lookAt(eye, target, up);
  camera.projection = glm::orthoRH_NO(-half_size, half_size, -half_size, half_size, 0.1f, 20.0f);
  camera.orthographic = true;
  return camera;
}

// A box from `lo` to `hi` on a square ground sheet at z = 0 reaching `ground_half` each way.
Scene box_on_ground(glm::vec3 lo, glm::vec3 hi, float ground_half) {
  Scene scene;
  scene.meshes = {reference::box(lo, hi),
                  reference::sheet({-ground_half, -ground_half}, {ground_half, ground_half}, 0.0f)};
  scene.instances = {{0, glm::mat4(1.0f)}, {1, glm::mat4(1.0f)}};
  return scene;
}

// Mean of the red channel of the image over pixels [x0, x1) x [y0, y1).
double mean_red(const RenderOutput& out, int x0, int y0, int x1, int y1) {
  double sum = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) sum += out.combined[4 * (size_t(y) * out.width + x)];
  return sum / double((x1 - x0) * (y1 - y0));
}

// The ground is 40 units wide, ten times the view: it only receives shadows,
// so it is left out of the SDF and the grid is fitted to the sphere alone (a
// grid over the ground would have voxels of a third of a unit). Its points
// outside the grid march from where their rays enter it.
TEST_F(RendererTest, SpherePenumbraMatchesAnalyticWidth) {
  const float radius = 0.5f, height = 1.0f;
  const float sun_angle = 10.0f * float(M_PI) / 180.0f;
  Scene scene;
  scene.meshes = {reference::uv_sphere({0, 0, height}, radius, 96), reference::sheet({-20, -20}, {20, 20}, 0.0f)};
  scene.instances = {{0, glm::mat4(1.0f), glm::vec3(0.8f)}, {1, glm::mat4(1.0f), glm::vec3(0.8f)}};
  GpuScene gpu_scene(context(), scene);

  const Camera camera = orthographic_view({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 2.0f);  // straight down, 4 x 4 world units
  Light sun;
  sun.type = LightType::Sun;
  // 45 degrees from overhead, shining towards +x: the shadow's far edge (near
  // x = 1.7) is beyond the sphere as the camera above sees it.
  const double tilt = M_PI / 4;
  sun.direction = {float(std::sin(tilt)), 0, -float(std::cos(tilt))};
  sun.energy = 3.0f;
  sun.sun_angle = sun_angle;
  RenderSettings settings;
  settings.samples = 8;
  const int size = 256;
  Renderer renderer(context());
  RenderOutput out = renderer.render(gpu_scene, camera, {sun}, glm::vec3(0.05f), size, size, settings);
  ASSERT_EQ(out.shadow.size(), size_t(size * size));
  if (const char* dump = std::getenv("RTSDF_TEST_DUMP")) {  // raw float planes for inspection
    FILE* f = std::fopen(dump, "wb");
    std::fwrite(out.shadow.data(), sizeof(float), out.shadow.size(), f);
    std::fwrite(out.combined.data(), sizeof(float), out.combined.size(), f);
    std::fclose(f);
  }

  // Row through y = 0: pixel i covers x = -2 + (i + 0.5) * 4 / size.
  const int row = size / 2;
  auto rendered = [&](double x) {
    int i = std::clamp(int((x + 2.0) / 4.0 * size), 0, size - 1);
    return double(out.shadow[size_t(row) * size + i]);
  };
  auto exact = [&](double x) {  // ground point (x, 0, 0); towards the sun: (-sin, 0, cos)
    glm::dvec3 to_center(-x, 0.0, height), to_sun(-std::sin(tilt), 0.0, std::cos(tilt));
    double d = glm::length(to_center);
    double offset = std::acos(std::clamp(glm::dot(to_center / d, to_sun), -1.0, 1.0));
    return 1.0 - hidden_share(0.5 * sun_angle, std::asin(radius / d), offset);
  };
  Profile r = profile(rendered, 1.0, 4.0 / size), e = profile(exact, 1.0, 0.001);
  std::printf("penumbra (10%%-90%%): rendered %.3f [%.3f..%.3f], analytic %.3f [%.3f..%.3f]; 50%% at %.3f vs %.3f; "
              "%d samples in %.0f ms\n", r.width(), r.x10, r.x90, e.width(), e.x10, e.x90, r.x50, e.x50,
              settings.samples, out.timings.total_ms);
  EXPECT_LT(rendered(1.0), 0.05) << "umbra at the shadow's centre";
  EXPECT_GT(rendered(1.97), 0.95) << "lit beyond it (the analytic penumbra ends near 1.92)";
  for (double x = 1.5; x <= 1.95; x += 0.05)
    EXPECT_NEAR(rendered(x), exact(x), 0.1) << "visibility along the penumbra at x = " << x;
  const double voxel = 4.0 / settings.fine_resolution;  // (of a grid over the visible 4 x 4; the real one is finer)
  EXPECT_NEAR(r.x50, e.x50, voxel) << "the shadow's edge (half the sun hidden) in its place";
  EXPECT_NEAR(r.width(), e.width(), 0.25 * e.width() + voxel) << "penumbra width";

  // Shading: a lit pixel of the plane is albedo * (sun cos / pi + ambient).
  const float lit = out.combined[4 * (size_t(row) * size + size - 3)];  // x = 1.96, past the penumbra
  EXPECT_NEAR(lit, 0.8f * (3.0f * float(std::cos(tilt)) / float(M_PI) + 0.05f), 0.02f);
  EXPECT_NEAR(out.depth[size_t(row) * size + size - 3], 10.0f, 0.01f);
}

// A quick first frame (the lights' visibility marched at one pixel of each
// 2x2 quad, shared along surfaces, marched anew where no quad's sample lies on
// the pixel's surface) shades every pixel the full frame does, alike. A box
// on the ground seen from above, the sun 45 degrees off overhead towards +x:
// the box's top is lit to its edge at x = 0.5, and the ground right beyond
// that edge lies in the box's shadow. The top's pixels along the edge must
// take nothing from the ground's samples. A wall under a pixel thick, along
// the middle of an odd column, has no quad sample on its top (frame 0 samples
// even columns): its pixels are shaded by the fill pass.
TEST_F(RendererTest, QuickFirstFrameSharesShadowsAlongSurfacesOnly) {
  Scene scene = box_on_ground({-0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 1.0f}, 20.0f);
  const int size = 128;
  const float wall_x = -2.0f + 17.5f * 4.0f / float(size);  // column 17's centre
  scene.meshes.push_back(reference::box({wall_x - 0.007f, -1.5f, 0.0f}, {wall_x + 0.007f, 1.5f, 0.5f}));
  scene.instances.push_back({2, glm::mat4(1.0f)});
  GpuScene gpu_scene(context(), scene);
  const Camera camera = orthographic_view({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 2.0f);
  Light sun;
  sun.type = LightType::Sun;
  const double tilt = M_PI / 4;
  sun.direction = {float(std::sin(tilt)), 0, -float(std::cos(tilt))};
  sun.energy = 3.0f;
  sun.sun_angle = 5.0f * float(M_PI) / 180.0f;
  RenderSettings settings;
  settings.samples = 1;
  Renderer renderer(context());
  // (the quick frame first, into fresh images: a pixel it left unshaded cannot keep the full frame's colour)
  settings.quick_first_frame = true;
  const RenderOutput quick = renderer.render(gpu_scene, camera, {sun}, glm::vec3(0.05f), size, size, settings);
  settings.quick_first_frame = false;
  const RenderOutput full = renderer.render(gpu_scene, camera, {sun}, glm::vec3(0.05f), size, size, settings);
  ASSERT_EQ(quick.combined.size(), full.combined.size());

  // Away from shadow edges (pixels whose full-frame visibility differs from
  // a neighbour's within 2 pixels, the reach of the quads' interpolation) the
  // two frames agree.
  auto full_at = [&](int x, int y) { return full.shadow[size_t(std::clamp(y, 0, size - 1)) * size + std::clamp(x, 0, size - 1)]; };
  auto near_edge = [&](int x, int y) {
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx)
        if (std::abs(full_at(x + dx, y + dy) - full_at(x, y)) > 0.05f) return true;
    return false;
  };
  int differing = 0, off_edges = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const size_t i = size_t(y) * size + x;
      ASSERT_EQ(quick.combined[4 * i + 3], full.combined[4 * i + 3]) << "pixel " << x << ", " << y << ": coverage";
      const float d = std::abs(quick.shadow[i] - full.shadow[i]);
      differing += d > 1e-6f;
      if (d > 0.05f && !near_edge(x, y)) {
        ++off_edges;
        ADD_FAILURE() << "pixel " << x << ", " << y << ": visibility " << quick.shadow[i] << " against " << full.shadow[i];
      }
    }
  std::printf("quick first frame: visibility differs at %d of %d pixels, by more than 0.05 at %d away from edges\n",
              differing, size * size, off_edges);
  EXPECT_GT(differing, 0) << "the quick frame shares visibility";

  // Pixel i covers x = -2 + (i + 0.5) * 4 / size: the top's last columns, then the shadowed ground's first.
  const int edge = size / 2 + size / 8;  // x = 0.5
  for (int y = size / 2 - size / 16; y < size / 2 + size / 16; ++y) {
    for (int i = edge - 3; i < edge; ++i)
      EXPECT_GT(quick.shadow[size_t(y) * size + i], 0.95f) << "the lit top at pixel " << i << ", row " << y;
    for (int i = edge; i < edge + 3; ++i)
      EXPECT_LT(quick.shadow[size_t(y) * size + i], 0.05f) << "the shadowed ground at pixel " << i << ", row " << y;
  }
}

// With more lights than ShadePass shares (it keeps a value per light and
// quad), a quick first frame marches them at every pixel: the same image.
TEST_F(RendererTest, QuickFirstFrameWithManyLightsMarchesEveryPixel) {
  GpuScene gpu_scene(context(), box_on_ground({-0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 1.0f}, 20.0f));
  const Camera camera = orthographic_view({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 2.0f);
  std::vector<Light> lights(ShadePass::kMaxSharedLights + 1);
  for (size_t i = 0; i < lights.size(); ++i) {
    lights[i].type = LightType::Point;
    lights[i].position = {2.0f * std::cos(0.4f * float(i)), 2.0f * std::sin(0.4f * float(i)), 2.0f};
    lights[i].energy = 10.0f;
  }
  RenderSettings settings;
  settings.samples = 1;
  const int size = 32;
  Renderer renderer(context());
  settings.quick_first_frame = true;
  const RenderOutput quick = renderer.render(gpu_scene, camera, lights, glm::vec3(0.0f), size, size, settings);
  settings.quick_first_frame = false;
  const RenderOutput full = renderer.render(gpu_scene, camera, lights, glm::vec3(0.0f), size, size, settings);
  ASSERT_EQ(quick.combined.size(), full.combined.size());
  for (size_t i = 0; i < quick.combined.size(); ++i) ASSERT_EQ(quick.combined[i], full.combined[i]) << "value " << i;
}

// The sub-pixel jitter follows Cycles' Blackman-Harris pixel filter: offsets
// from evenly spread shares have the window's spread (its variance, by direct
// integration of the window), lie within it and are symmetric; width 0 is a box.
TEST(PixelFilter, JitterIsDistributedAsTheBlackmanHarrisWindow) {
  const float width = 1.5f, half_span = width;  // the window spans twice the width
  auto window = [&](double x) {
    const double v = 6.283185307 * (x / (2.0 * half_span) + 0.5);
    return 0.35875 - 0.48829 * std::cos(v) + 0.14128 * std::cos(2 * v) - 0.01168 * std::cos(3 * v);
  };
  double weight = 0.0, moment = 0.0;
  const int steps = 20000;
  for (int i = 0; i < steps; ++i) {
    const double x = -half_span + (i + 0.5) * 2.0 * half_span / steps;
    weight += window(x), moment += window(x) * x * x;
  }
  const double window_variance = moment / weight;
  double sum = 0.0, sum_squares = 0.0;
  const int samples = 4096;
  for (int i = 0; i < samples; ++i) {
    const float x = pixel_filter_offset((float(i) + 0.5f) / float(samples), width);
    EXPECT_LE(std::abs(x), half_span);
    sum += x, sum_squares += double(x) * x;
  }
  EXPECT_NEAR(sum / samples, 0.0, 1e-3);
  EXPECT_NEAR(sum_squares / samples, window_variance, 0.01 * window_variance);
  EXPECT_NEAR(pixel_filter_offset(0.25f, width), -pixel_filter_offset(0.75f, width), 1e-4);
  EXPECT_FLOAT_EQ(pixel_filter_offset(0.25f, 0.0f), -0.25f);
}

// Renderers of one context share its compiled pipelines: a second one, as
// a new viewport or the next F12 render makes, compiles nothing.
TEST_F(RendererTest, ASecondRendererOfAContextMakesNoPipeline) {
  GpuScene scene(context(), box_on_ground({-0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 1.0f}, 4.0f));
  const Camera camera = orthographic_view({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 2.0f);
  Light sun;
  sun.type = LightType::Sun;
  sun.direction = glm::normalize(glm::vec3(0.3f, 0.2f, -1.0f));
  sun.sun_angle = 0.1f;
  RenderSettings settings;
  settings.samples = 2;
  { Renderer(context()).render(scene, camera, {sun}, glm::vec3(0.1f), 32, 32, settings); }
  const size_t made = context().shared_object_count();
  EXPECT_GT(made, 0u);
  RenderOutput again = Renderer(context()).render(scene, camera, {sun}, glm::vec3(0.1f), 32, 32, settings);
  EXPECT_EQ(context().shared_object_count(), made);
  EXPECT_EQ(again.combined.size(), size_t(4 * 32 * 32));
}

TEST_F(RendererTest, BadSizesAndLightsAreErrors) {
  GpuScene scene(context(), single_mesh_scene(reference::box({-1, -1, -1}, {1, 1, 1})));
  Renderer renderer(context());
  Camera camera;
  Light bad;
  bad.energy = std::nanf("");
  EXPECT_THROW(renderer.render(scene, camera, {}, glm::vec3(0), 0, 10, {}), Error);
  EXPECT_THROW(renderer.render(scene, camera, {bad}, glm::vec3(0), 8, 8, {}), Error);
  RenderSettings no_filter;
  no_filter.filter_width = std::nanf("");
  EXPECT_THROW(renderer.render(scene, camera, {}, glm::vec3(0), 8, 8, no_filter), Error);
}

}  // namespace
}  // namespace rtsdf

namespace rtsdf {
namespace {

TEST_F(RendererTest, ProgressIsReportedAndCanStopTheRender) {
  GpuScene scene(context(), single_mesh_scene(reference::box({-1, -1, -1}, {1, 1, 1})));
  Camera camera;
  camera.world_to_view = glm::lookAt(glm::vec3(3, 3, 3), glm::vec3(0), glm::vec3(0, 0, 1));
  camera.projection = glm::perspectiveRH_NO(0.8f, 1.0f, 0.1f, 20.0f);
  RenderSettings settings;
  settings.samples = 6;
  std::vector<int> reported;
  Renderer renderer(context());
  RenderOutput out = renderer.render(scene, camera, {}, glm::vec3(0.5f), 16, 16, settings, [&](int done, int total) {
    reported.push_back(done);
    EXPECT_EQ(total, 6);
    return done < 2;  // stop after the second frame
  });
  EXPECT_EQ(reported, (std::vector<int>{1, 2}));
  EXPECT_EQ(out.samples_done, 2);
  // What was done is in the output: the box is covered and lit by the world.
  EXPECT_NEAR(out.combined[4 * (8 * 16 + 8)], 0.8f * 0.5f, 1e-3f);
}

// A final render's grid is fitted to its own scene, whatever was rendered
// before with room around the casters (only the viewport and persistent
// data keep a grid, for its history).
TEST_F(RendererTest, FinalRenderDoesNotInheritAnEarlierGrid) {
  Scene large = single_mesh_scene(reference::box({-2, -2, 0}, {2, 2, 1}));
  Scene small = single_mesh_scene(reference::box({-1.8f, -1.8f, 0}, {1.8f, 1.8f, 1}));  // fits the first grid
  GpuScene large_scene(context(), large), small_scene(context(), small);
  Camera camera;
  camera.world_to_view = glm::lookAt(glm::vec3(3, 3, 3), glm::vec3(0), glm::vec3(0, 0, 1));
  camera.projection = glm::perspectiveRH_NO(0.8f, 1.0f, 0.1f, 20.0f);
  RenderSettings settings;
  settings.samples = 2;
  settings.grid_slack = 0.5f;
  settings.coarse_resolution = 32;
  settings.fine_resolution = 64;
  Light sun;
  sun.direction = glm::normalize(glm::vec3(-1, -0.5f, -2));
  sun.sun_angle = 0.1f;
  Renderer used(context()), fresh(context());
  used.render(large_scene, camera, {sun}, glm::vec3(0.2f), 24, 24, settings);
  RenderOutput after = used.render(small_scene, camera, {sun}, glm::vec3(0.2f), 24, 24, settings);
  RenderOutput alone = fresh.render(small_scene, camera, {sun}, glm::vec3(0.2f), 24, 24, settings);
  EXPECT_EQ(after.combined, alone.combined);
}

}  // namespace
}  // namespace rtsdf

namespace rtsdf {
namespace {

// A box resting on a ground that only receives: its shadow starts right at
// its foot, with no lit gap (the ground's marches start on the ground, as
// nothing of the ground is in the SDF).
TEST_F(RendererTest, ShadowOfAnObjectRestingOnTheGroundStartsAtItsFoot) {
  GpuScene gpu_scene(context(), box_on_ground({-0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 1.0f}, 5.0f));
  const Camera camera = orthographic_view({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 2.0f);  // straight down, x and y in [-2, 2]
  Light sun;  // 45 degrees, towards +x: the shadow covers x in [0.5, 1.5] behind the box
  sun.type = LightType::Sun;
  sun.direction = {1.0f, 0.0f, -1.0f};
  sun.sun_angle = 2.0f * float(M_PI) / 180.0f;
  RenderSettings settings;
  settings.samples = 2;
  const int size = 128;
  Renderer renderer(context());
  RenderOutput out = renderer.render(gpu_scene, camera, {sun}, glm::vec3(0.0f), size, size, settings);
  EXPECT_EQ(gpu_scene.shadow_casters(), (std::vector<uint32_t>{0})) << "only the box is in the SDF";
  const int row = size / 2;
  // Pixel i covers x in [-2 + 4i/size, -2 + 4(i+1)/size]: the first pixel wholly past the foot, out to x = 1.3.
  for (int i = int(std::ceil((0.5 + 2.0) * size / 4.0)); -2.0 + 4.0 * (i + 1) / size < 1.3; ++i)
    EXPECT_LT(out.shadow[size_t(row) * size + i], 0.1f) << "ground at x = " << -2.0 + 4.0 * (i + 0.5) / size;
  EXPECT_GT(out.shadow[size_t(row) * size + size - 10], 0.99f) << "lit beyond the shadow";
}

}  // namespace
}  // namespace rtsdf

namespace rtsdf {
namespace {

TEST_F(RendererTest, WritesAllPassesToOpenExr) {
  GpuScene scene(context(), single_mesh_scene(reference::box({-1, -1, -1}, {1, 1, 1})));
  Camera camera;
  camera.world_to_view = glm::lookAt(glm::vec3(3, 3, 3), glm::vec3(0), glm::vec3(0, 0, 1));
  camera.projection = glm::perspectiveRH_NO(0.8f, 1.0f, 0.1f, 20.0f);
  Light sun;
  sun.direction = {-0.3f, -0.2f, -1.0f};
  RenderSettings settings;
  settings.samples = 1;
  Renderer renderer(context());
  const RenderOutput out = renderer.render(scene, camera, {sun}, glm::vec3(0.1f), 12, 8, settings);
  const std::string path = ::testing::TempDir() + "rtsdf_passes.exr";
  write_exr(path, out);

  Imf::InputFile file(path.c_str());
  const Imath::Box2i window = file.header().dataWindow();
  ASSERT_EQ(window.max.x - window.min.x + 1, 12);
  ASSERT_EQ(window.max.y - window.min.y + 1, 8);
  std::vector<float> channels[6];
  const char* names[6] = {"R", "G", "B", "A", "Z", "Shadow"};
  Imf::FrameBuffer frame;
  for (int c = 0; c < 6; ++c) {
    ASSERT_NE(file.header().channels().findChannel(names[c]), nullptr) << names[c];
    channels[c].resize(12 * 8);
    frame.insert(names[c], Imf::Slice(Imf::FLOAT, (char*)channels[c].data(), sizeof(float), 12 * sizeof(float)));
  }
  file.setFrameBuffer(frame);
  file.readPixels(window.min.y, window.max.y);
  for (size_t i = 0; i < 12 * 8; ++i) {
    for (int c = 0; c < 4; ++c) EXPECT_EQ(channels[c][i], out.combined[4 * i + c]);
    EXPECT_EQ(channels[4][i], out.depth[i]);
    EXPECT_EQ(channels[5][i], out.shadow[i]);
  }
  EXPECT_THROW(write_exr("/nonexistent-dir/x.exr", out), Error);
  EXPECT_THROW(write_exr(path, RenderOutput{}), Error);
}

}  // namespace
}  // namespace rtsdf

namespace rtsdf {
namespace {

// The world light is occluded through the SDF: the ground under a wide roof
// sees little sky, the open ground all of it. (Open: 6 units from the roof,
// which hides 0.2% of the sky there; at 2.2 units it hid 2.6%, near the
// tolerance.)
TEST_F(RendererTest, WorldLightIsOccludedUnderARoof) {
  GpuScene gpu_scene(context(), box_on_ground({-1.5f, -1.5f, 0.6f}, {1.5f, 1.5f, 0.8f}, 20.0f));
  // Straight down: the roof and the ground around it.
  const Camera camera = orthographic_view({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 8.0f);
  RenderSettings settings;
  settings.samples = 16;
  const int size = 128;
  Renderer renderer(context());
  // No lights: only the world colour (0.5) lights the ground (albedo 0.8).
  RenderOutput out = renderer.render(gpu_scene, camera, {}, glm::vec3(0.5f), size, size, settings);
  // Mean of the 5x5 pixels around world (x, 0): each pixel holds only 32 sky
  // samples (two a frame), and a sample is either blocked or not.
  auto ground_at = [&](double x) {
    const int i = std::clamp(int((x + 8.0) / 16.0 * size), 2, size - 3);
    return float(mean_red(out, i - 2, size / 2 - 2, i + 3, size / 2 + 3));
  };
  const float open = 0.8f * 0.5f;
  EXPECT_NEAR(ground_at(7.5), open, 0.03f * open) << "open ground sees the whole sky";
  EXPECT_LT(ground_at(1.9), open) << "next to the roof, part of the sky is hidden";
  EXPECT_NEAR(out.combined[4 * (size_t(size / 2) * size + size / 2)], 0.8f * 0.5f, 0.01f)
      << "the roof's top (seen from above) sees the whole sky";
}

// A ground left out of the SDF (flat, under everything) still hides the
// lower half of the sky: a pillar's side sees only the upper half, half of
// what a vertical surface sees under an open sky (cosine-weighted). The
// ground reaches far: beyond the edge of one 20 units wide the sky shows
// again just below the horizon, and the side saw 0.215-0.218 over 256
// frames (raytraced as well: 0.215), not the endless ground's 0.20.
TEST_F(RendererTest, GroundLeftOutOfTheSdfStillHidesTheSkyBelow) {
  GpuScene gpu_scene(context(), box_on_ground({-0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 3.0f}, 1000.0f));
  const Camera camera = orthographic_view({0, -10, 1.5f}, {0, 0, 1.5f}, {0, 0, 1}, 1.0f);  // level, at the -y side
  RenderSettings settings;
  settings.samples = 16;
  settings.coarse_resolution = 32;
  settings.fine_resolution = 64;
  const int size = 16;
  Renderer renderer(context());
  RenderOutput out = renderer.render(gpu_scene, camera, {}, glm::vec3(0.5f), size, size, settings);
  const double side = mean_red(out, 6, 6, 10, 10), open = 0.8 * 0.5;
  std::printf("pillar side: %.3f (open sky %.2f; the upper half %.2f)\n", side, open, 0.5 * open);
  EXPECT_NEAR(side, 0.5 * open, 0.1 * 0.5 * open);
}

// Renders (32x32, 8 frames) the floor of a closed room 4 units wide whose
// floor, walls and ceiling are 0.1 thick, seen from inside, under `lights`
// and a world of colour `ambient`.
RenderOutput render_closed_room_floor(const vk::Context& context, const std::vector<Light>& lights, glm::vec3 ambient) {
  Mesh room = reference::box({-2.1f, -2.1f, -0.1f}, {2.1f, 2.1f, 0.0f});  // floor
  reference::append(room, reference::box({-2.1f, -2.1f, 2.5f}, {2.1f, 2.1f, 2.6f}));  // ceiling
  reference::append(room, reference::box({-2.1f, -2.1f, 0.0f}, {-2.0f, 2.1f, 2.5f}));
  reference::append(room, reference::box({2.0f, -2.1f, 0.0f}, {2.1f, 2.1f, 2.5f}));
  reference::append(room, reference::box({-2.0f, -2.1f, 0.0f}, {2.0f, -2.0f, 2.5f}));
  reference::append(room, reference::box({-2.0f, 2.0f, 0.0f}, {2.0f, 2.1f, 2.5f}));
  GpuScene scene(context, single_mesh_scene(room));
  Camera camera;  // inside, looking down at the floor
  camera.world_to_view = glm::lookAt(glm::vec3(0, 0, 2.0f), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
  camera.projection = glm::perspectiveRH_NO(1.2f, 1.0f, 0.1f, 20.0f);
  RenderSettings settings;
  settings.samples = 8;
  settings.coarse_resolution = 32;
  settings.fine_resolution = 64;
  Renderer renderer(context);
  return renderer.render(scene, camera, lights, ambient, 32, 32, settings);
}

// A closed room whose walls are much thinner than the sky's cones are wide:
// no world light inside. By the clearance inside the walls alone (about
// -thickness / 2 against cones metres wide) half the sky shone through them.
TEST_F(RendererTest, NoWorldLightInsideAClosedRoom) {
  RenderOutput out = render_closed_room_floor(context(), {}, glm::vec3(0.5f));
  const double mean = mean_red(out, 0, 0, out.width, out.height), open = 0.8 * 0.5;
  std::printf("floor of a closed room: mean %.4f (open sky would give %.2f)\n", mean, open);
  EXPECT_LT(mean, 0.05 * open);
}

// Nor any sun: a wide, low sun's cone is wider than the walls and the ceiling
// are thick where it crosses them, and the clearance inside them tells only
// their thickness (a sixth of the sun came through before the march told a
// sheet from the rim of a solid).
TEST_F(RendererTest, NoSunInsideAClosedRoomWithThinWalls) {
  Light sun;
  sun.type = LightType::Sun;
  sun.direction = glm::normalize(glm::vec3(0.8f, 0.2f, -0.5f));  // 32 degrees above the horizon
  sun.energy = 3.0f;
  sun.sun_angle = 10.0f * float(M_PI) / 180.0f;
  RenderOutput out = render_closed_room_floor(context(), {sun}, glm::vec3(0.0f));
  double lit = 0.0, bright = 0.0;
  for (float v : out.shadow) lit += v, bright += v > 0.05f ? 1.0 : 0.0;
  lit /= double(out.shadow.size()), bright /= double(out.shadow.size());
  std::printf("sun on the floor of a closed room: mean %.4f of the unshadowed sun, %.1f%% of pixels above 0.05\n", lit,
              100.0 * bright);
  EXPECT_LT(lit, 0.01);
  // (the seams where a wall meets the ceiling read as cracks: boxes that touch leave faces inside the solid)
  EXPECT_LT(bright, 0.02);
}

// Nor at a corner: the inner face of a wall that faces the sun, where it
// meets the wall the sun's rays must cross. A receiver in the SDF started its
// march a voxel along the ray and escaped its own shell (thin pieces read as
// slabs) by skipping negative samples for two more; at a corner those were
// the other wall's, which the ray crossed in as much, and a seam of sunlight
// ran up the corner (beside the interior sample's window: 0.09 of the
// unshadowed sun; none in Cycles). Here, at the presets' field resolution
// (walls 2 voxels thick), 60 pixels were lit by the march alone and 48 with
// exact rays. Thinner walls are at the field's limit: from Python, at 64
// voxels (1.4 thick) about 1,000 of 128x128 pixels still are by the march
// alone (2,200 before), 1 with exact rays (2,000 before); at 128 voxels 64
// by the march alone (358 before), none with exact rays (99 before).
TEST_F(RendererTest, NoSunThroughTheWallAtACornerOfAClosedRoom) {
  Light sun;
  sun.type = LightType::Sun;
  sun.direction = glm::normalize(glm::vec3(0.8f, 0.2f, -0.5f));  // through the -x wall onto the +y wall's inside
  sun.energy = 3.0f;
  sun.sun_angle = 3.0f * float(M_PI) / 180.0f;
  Mesh room = reference::box({-2.1f, -2.1f, -0.1f}, {2.1f, 2.1f, 0.0f});
  reference::append(room, reference::box({-2.1f, -2.1f, 2.5f}, {2.1f, 2.1f, 2.6f}));
  reference::append(room, reference::box({-2.1f, -2.1f, 0.0f}, {-2.0f, 2.1f, 2.5f}));
  reference::append(room, reference::box({2.0f, -2.1f, 0.0f}, {2.1f, 2.1f, 2.5f}));
  reference::append(room, reference::box({-2.0f, -2.1f, 0.0f}, {2.0f, -2.0f, 2.5f}));
  reference::append(room, reference::box({-2.0f, 2.0f, 0.0f}, {2.0f, 2.1f, 2.5f}));
  GpuScene scene(context(), single_mesh_scene(room));
  Camera camera;  // inside, looking into the corner of the -x and +y walls from a metre and a half away
  camera.world_to_view = glm::lookAt(glm::vec3(-1.0f, 1.0f, 1.25f), glm::vec3(-2.0f, 2.0f, 1.25f), glm::vec3(0, 0, 1));
  camera.projection = glm::perspectiveRH_NO(0.5f, 1.0f, 0.1f, 20.0f);
  for (int exact_rays : {0, 4}) {
    RenderSettings settings;
    settings.samples = 8;
    settings.coarse_resolution = 64;
    settings.fine_resolution = 96;
    settings.exact_rays = exact_rays;
    Renderer renderer(context());
    const RenderOutput out = renderer.render(scene, camera, {sun}, glm::vec3(0.0f), 32, 32, settings);
    // (no world light: any colour is sun; the +y wall's inside, lit, would read about 0.15)
    double brightest = 0.0, lit = 0.0;
    for (size_t i = 0; i < out.combined.size(); i += 4) {
      brightest = std::max(brightest, double(out.combined[i]));
      lit += out.combined[i] > 0.01f ? 1.0 : 0.0;
    }
    std::printf("sun at the corner of a closed room (exact rays %d): brightest pixel %.4f, %.0f pixels above 0.01\n",
                exact_rays, brightest, lit);
    EXPECT_LT(brightest, 0.01);
  }
}

// A room built as an Archimesh room is: its walls one mesh of boxes that
// overlap at the corners, its ceiling a slab of its own resting on them,
// its floor a sheet; a low sun outside. At the Preview preset's resolution
// (walls two voxels thick) and without exact rays, no sun reaches the floor.
// Rays that cross a wall at the room's corner, or pass where a wall's top
// meets the ceiling, stay within a voxel of the walls' surfaces all through
// (the field cannot be deeper than half a wall), and leave by a face at a
// right angle to the one they entered by: the cone read a third of the sun
// through, in lines of light across the floor (288 of the 6,992 floor
// pixels here, 4%; the interior sample's Preview had them too, none in
// Cycles). Then 60: seams crossed in under two and a half voxels keep the
// cone's estimate (see visibility() in shaders/sdf_march.glsl.h), and where
// the ceiling's field touches the walls' the two read about 0, a hairline
// between the solids that rays crossed. Now 0: a point within a quarter
// voxel of two fields' surfaces reads as inside (nearby_distance in
// shaders/sdf_fields.glsl.h).
TEST_F(RendererTest, NoSunThroughTheCornersAndCeilingSeamsOfAThinWalledRoom) {
  Mesh walls = reference::box({-3.15f, -2.65f, 0.0f}, {-3.0f, 2.65f, 2.7f});
  reference::append(walls, reference::box({3.0f, -2.65f, 0.0f}, {3.15f, 2.65f, 2.7f}));
  reference::append(walls, reference::box({-3.15f, -2.65f, 0.0f}, {3.15f, -2.5f, 2.7f}));
  reference::append(walls, reference::box({-3.15f, 2.5f, 0.0f}, {3.15f, 2.65f, 2.7f}));
  Scene scene;
  scene.meshes = {walls, reference::box({-3.15f, -2.65f, 2.7f}, {3.15f, 2.65f, 2.85f}),
                  reference::sheet({-3.0f, -2.5f}, {3.0f, 2.5f}, 0.0f)};
  scene.instances = {{0, glm::mat4(1.0f)}, {1, glm::mat4(1.0f)}, {2, glm::mat4(1.0f)}};
  GpuScene gpu_scene(context(), scene);
  Light sun;
  sun.type = LightType::Sun;
  sun.direction = glm::normalize(glm::vec3(0.82f, 0.22f, -0.53f));  // 32 degrees up, across the -x wall's corners
  sun.energy = 3.0f;
  sun.sun_angle = 3.0f * float(M_PI) / 180.0f;
  RenderSettings settings;  // (the Preview preset's fields, no exact rays)
  settings.samples = 8;
  settings.coarse_resolution = 64;
  settings.fine_resolution = 96;
  settings.exact_rays = 0;
  Renderer renderer(context());
  // From under the ceiling, straight down: 6 x 6 units over 96 pixels.
  const Camera camera = orthographic_view({0.0f, 0.0f, 2.6f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 3.0f);
  const RenderOutput out = renderer.render(gpu_scene, camera, {sun}, glm::vec3(0.0f), 96, 96, settings);
  double brightest = 0.0;
  int lit = 0, floor = 0;
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      // (the floor away from the walls: the camera, under the ceiling, is inside the walls at the image's sides)
      const float wx = (x + 0.5f) / out.width * 6.0f - 3.0f, wy = 3.0f - (y + 0.5f) / out.height * 6.0f;
      if (std::abs(wx) > 2.9f || std::abs(wy) > 2.4f) continue;
      const double v = out.combined[4 * (size_t(y) * out.width + x)];
      brightest = std::max(brightest, v), lit += v > 0.01 ? 1 : 0, floor++;
    }
  std::printf("floor of a thin-walled room under a low sun, no exact rays: brightest %.4f, %d of %d pixels above 0.01\n",
              brightest, lit, floor);
  EXPECT_LE(lit, floor / 500);
}

// Two parts of an assembly, each its own mesh (so its own field), touching
// face to face, under a sun whose rays run along their contact: the ground
// behind them is in their shadow all through. Each field reads about 0 at
// its own face, and their minimum, a hairline of clearance between the two,
// let the rays through: a line of light across the shadow where Cycles has
// none (as where the interior sample's walls meet its ceiling).
TEST_F(RendererTest, NoLightThroughTheContactOfTwoTouchingParts) {
  Scene scene;
  scene.meshes = {reference::box({-0.5f, -0.5f, 0.0f}, {0.0f, 0.5f, 1.0f}),
                  reference::box({0.0f, -0.5f, 0.0f}, {0.5f, 0.5f, 1.0f}),
                  reference::sheet({-3.0f, -4.0f}, {3.0f, 2.0f}, 0.0f)};
  scene.instances = {{0, glm::mat4(1.0f)}, {1, glm::mat4(1.0f)}, {2, glm::mat4(1.0f)}};
  GpuScene gpu_scene(context(), scene);
  Light sun;
  sun.type = LightType::Sun;
  sun.direction = glm::normalize(glm::vec3(0.0f, -0.8f, -0.6f));  // (in the plane of the contact, x = 0)
  sun.energy = 3.0f;
  sun.sun_angle = 3.0f * float(M_PI) / 180.0f;
  RenderSettings settings;  // (no exact rays: the field alone decides)
  settings.samples = 8;
  settings.exact_rays = 0;
  Renderer renderer(context());
  // The umbra behind the parts (it reaches 1.33 behind them), from above: x and y within 0.4 of (0, -1.1).
  const Camera camera = orthographic_view({0.0f, -1.1f, 5.0f}, {0.0f, -1.1f, 0.0f}, {0, 1, 0}, 0.4f);
  const RenderOutput out = renderer.render(gpu_scene, camera, {sun}, glm::vec3(0.0f), 33, 33, settings);
  double brightest = 0.0;
  for (float v : out.shadow) brightest = std::max(brightest, double(v));
  std::printf("umbra behind two touching parts, the sun along their contact: brightest visibility %.4f\n", brightest);
  EXPECT_LT(brightest, 0.05);
}

// A low sun behind a wall 8 units away, and on the way a small object (its
// own mesh, so its own field, voxels a hundredth of the wall's) half a unit
// beside the rays: the ground stays in the wall's shadow. The march's steps
// were sized by the voxels of the field nearest by bound, the small
// object's, for most of the way; the rays ran out of steps before they
// reached the wall, and light came through it (an Archimesh room's window
// frame lit twice the floor Cycles lit).
TEST_F(RendererTest, SmallObjectNearTheRaysDoesNotLetLightThroughAWall) {
  // The wall's mesh has a second part far off (as a room's walls surround
  // it), so that its field's box holds the rays' whole way.
  Mesh wall = reference::box({0.0f, -5.0f, 0.0f}, {0.2f, 5.0f, 10.0f});
  reference::append(wall, reference::box({-9.9f, -4.9f, 9.8f}, {-9.8f, -4.8f, 9.9f}));
  Scene scene;
  scene.meshes = {wall, reference::box({-4.05f, 0.45f, 0.7f}, {-3.95f, 0.55f, 0.8f}),  // and the small object
                  reference::sheet({-10.0f, -5.0f}, {0.0f, 5.0f}, 0.0f)};            // on the ground
  scene.instances = {{0, glm::mat4(1.0f)}, {1, glm::mat4(1.0f)}, {2, glm::mat4(1.0f)}};
  GpuScene gpu_scene(context(), scene);
  Light sun;
  sun.type = LightType::Sun;
  const float elevation = 10.0f * float(M_PI) / 180.0f;  // (the rays reach the wall 1.4 up)
  sun.direction = {-std::cos(elevation), 0.0f, -std::sin(elevation)};
  sun.energy = 3.0f;
  sun.sun_angle = 0.5f * float(M_PI) / 180.0f;
  RenderSettings settings;
  settings.samples = 2;
  Renderer renderer(context());
  // The ground around x = -8, y = 0 from above.
  const Camera camera = orthographic_view({-8.0f, 0.0f, 5.0f}, {-8.0f, 0.0f, 0.0f}, {0, 1, 0}, 0.5f);
  const RenderOutput out = renderer.render(gpu_scene, camera, {sun}, glm::vec3(0.0f), 16, 16, settings);
  double sum = 0.0, brightest = 0.0;
  for (float v : out.shadow) sum += v, brightest = std::max(brightest, double(v));
  std::printf("ground behind a wall, a small object near the rays: mean visibility %.4f, brightest %.4f\n",
              sum / double(out.shadow.size()), brightest);
  EXPECT_LT(brightest, 0.05);
}

}  // namespace
}  // namespace rtsdf
