// Temporal reuse (Renderer with RenderSettings::temporal_reuse, the viewport's
// playback): the G-buffer's motion, history kept where the same surface shows
// and dropped where another does, and no shadow left behind a moved caster.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <tuple>
#include <glm/gtc/matrix_transform.hpp>

#include "reference/shapes.h"
#include "renderer.h"
#include "top_view.h"
#include "vulkan_test.h"

namespace rtsdf {
namespace {

using testing::tilted_sun;
using testing::top_view;

constexpr int kSize = 64;  // pixels over the 4 x 4 top view

class TemporalTest : public testing::VulkanTest {};

// A cube 0.5 wide standing 0.5 above a ground, at x = -0.5; moved by
// kMove along +x. The sun is tilted 45 degrees towards +x.
constexpr float kMove = 0.5f;

Scene cube_over_ground() {
  Scene scene;
  scene.meshes = {reference::box({-0.25f, -0.25f, 0.5f}, {0.25f, 0.25f, 1.0f}), reference::sheet({-20, -20}, {20, 20}, 0.0f)};
  scene.instances = {{0, glm::translate(glm::mat4(1.0f), glm::vec3(-0.5f, 0, 0)), glm::vec3(0.8f)},
                     {1, glm::mat4(1.0f), glm::vec3(0.8f)}};
  return scene;
}

RenderSettings playback_settings() {
  RenderSettings settings;
  settings.coarse_resolution = 32;
  settings.fine_resolution = 64;
  settings.keep_history = true;
  settings.temporal_reuse = true;
  return settings;
}

size_t pixel_at(double x, double y) {  // (rows top to bottom: +y first)
  const int i = std::clamp(int((x + 2.0) / 4.0 * kSize), 0, kSize - 1);
  const int j = std::clamp(int((2.0 - y) / 4.0 * kSize), 0, kSize - 1);
  return size_t(j) * kSize + size_t(i);
}

void move_cube(GpuScene& scene, float x) {
  scene.set_transforms({glm::translate(glm::mat4(1.0f), glm::vec3(x, 0, 0)), glm::mat4(1.0f)});
}

// Begins a frame of `scene` from the top view (a playback frame where it
// changed) and draws `frames` frames of it.
void draw_top_view(Renderer& renderer, GpuScene& scene, const std::vector<Light>& lights, glm::vec3 sky,
                   const RenderSettings& settings, int frames, glm::ivec2 size = {kSize, kSize}) {
  renderer.begin(scene, top_view(), lights, sky, size.x, size.y, settings, true);
  for (int frame = 0; frame < frames; ++frame) renderer.add_frame();
}

// A pixel's mean of R, G and B (a sky's noise shows there, not in the Shadow pass).
float brightness(const RenderOutput& out, size_t i) {
  return (out.combined[4 * i] + out.combined[4 * i + 1] + out.combined[4 * i + 2]) / 3.0f;
}

// The mean change of brightness between two images over `pixels`.
double mean_change(const RenderOutput& a, const RenderOutput& b, const std::vector<size_t>& pixels) {
  double sum = 0.0;
  for (size_t i : pixels) sum += std::abs(brightness(a, i) - brightness(b, i));
  return sum / double(pixels.size());
}

// One sample's noise over `pixels`: how far a frame of its own, without
// history, is from the `converged` image.
double one_sample_noise(GpuScene& scene, const std::vector<Light>& lights, glm::vec3 sky, RenderSettings settings,
                        const RenderOutput& converged, const std::vector<size_t>& pixels) {
  Renderer single(testing::VulkanTest::context());
  settings.temporal_reuse = false;
  draw_top_view(single, scene, lights, sky, settings, 1);
  return mean_change(single.read(), converged, pixels);
}

// The tilted sun with a wide, noisy penumbra.
Light wide_sun() {
  Light sun = tilted_sun();
  sun.sun_angle = float(20.0 * M_PI / 180.0);
  return sun;
}

// cube_over_ground's cube at (moving_x, moving_y), which moves, and a second
// one, still, at (-0.5, still_y): the transforms, then the scene.
std::vector<glm::mat4> two_cubes_at(float moving_x, float moving_y, float still_y) {
  return {glm::translate(glm::mat4(1.0f), glm::vec3(moving_x, moving_y, 0)), glm::mat4(1.0f),
          glm::translate(glm::mat4(1.0f), glm::vec3(-0.5f, still_y, 0))};
}

Scene two_cubes(float moving_y, float still_y) {
  Scene scene = cube_over_ground();
  const std::vector<glm::mat4> at = two_cubes_at(-0.5f, moving_y, still_y);
  scene.instances[0].object_to_world = at[0];
  scene.instances.push_back({0, at[2], glm::vec3(0.8f)});
  return scene;
}

// After 4 frames, the cube moves: the G-buffer's motion on its top is the
// analytic one (the top view maps 4 units to 2 in normalized coordinates),
// 0 on the ground; history carries over on the still ground (4 samples) and
// on the cube's top, and is dropped where the ground shows through where the
// cube was (its depth differs by a tenth).
TEST_F(TemporalTest, ReprojectionFollowsATranslatingCubeAndDropsDisocclusions) {
  GpuScene scene(context(), cube_over_ground());
  Renderer renderer(context());
  const RenderSettings settings = playback_settings();
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 4);
  move_cube(scene, -0.5f + kMove);
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 1);

  const std::vector<glm::vec4> motion = renderer.read_motion();
  const glm::vec4 on_top = motion[pixel_at(0.05, 0.05)], on_ground = motion[pixel_at(1.8, 1.8)];
  std::printf("motion on the cube's top (%.4f, %.4f), depth %.3f; on the ground (%.4f, %.4f)\n", on_top.x, on_top.y,
              on_top.z, on_ground.x, on_ground.y);
  EXPECT_NEAR(on_top.x, -kMove * 0.5f, 1e-4f);
  EXPECT_NEAR(on_top.y, 0.0f, 1e-4f);
  EXPECT_NEAR(on_top.z, 9.0f, 1e-3f) << "the top's depth from the camera 10 above the ground";
  EXPECT_EQ(on_top.w, 1.0f);
  EXPECT_NEAR(on_ground.x, 0.0f, 1e-5f);
  EXPECT_NEAR(on_ground.y, 0.0f, 1e-5f);

  const RenderOutput out = renderer.read();
  const float ground = out.samples[pixel_at(1.8, 1.8)], top = out.samples[pixel_at(0.05, 0.05)];
  const float uncovered = out.samples[pixel_at(-0.6, 0.0)];
  std::printf("samples: still ground %.0f, cube top %.0f, ground where the cube was %.0f; effective %.2f\n", ground, top,
              uncovered, out.effective_samples);
  EXPECT_EQ(ground, 5.0f) << "4 frames of history and this one";
  EXPECT_GE(top, 2.0f) << "the moved top found itself in history";
  EXPECT_EQ(uncovered, 1.0f) << "history there showed the cube: dropped";
  EXPECT_GT(out.effective_samples, 3.0);
}

// The cube sinks by 0.2, away from the camera (its top's depth 9 -> 9.2,
// twice the reprojection's depth tolerance): its top's history is still its
// own, compared at the depths it has now, and keeps its 4 samples (with
// history's depths left at the last frame's, its nearest depth lay in front
// of the top, as if something that moved had been there, and history counted
// as 3).
TEST_F(TemporalTest, ASurfaceMovingAwayFromTheCameraKeepsItsHistory) {
  GpuScene scene(context(), cube_over_ground());
  Renderer renderer(context());
  const RenderSettings settings = playback_settings();
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 4);
  scene.set_transforms({glm::translate(glm::mat4(1.0f), glm::vec3(-0.5f, 0, -0.2f)), glm::mat4(1.0f)});
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 1);
  const RenderOutput out = renderer.read();
  const size_t top = pixel_at(-0.5, 0.0);
  std::printf("the sunk top: depth %.3f, samples %.0f\n", out.depth[top], out.samples[top]);
  EXPECT_NEAR(out.depth[top], 9.2f, 1e-3f);
  EXPECT_EQ(out.samples[top], 5.0f) << "4 frames of history and this one";
}

// The cube moves by three quarters of its width: the ground a pixel behind
// its new outline was under the cube, and that pixel's own history (the
// cube) is dropped; read where the outline was (the motion of the nearer
// surface beside it), it finds the ground beside the old outline, with its
// samples and their anti-aliased edge. A pixel farther behind, out of the
// outline's reach, starts afresh.
TEST_F(TemporalTest, APixelBehindAMovingOutlineReadsHistoryWhereTheOutlineWas) {
  GpuScene scene(context(), cube_over_ground());
  Renderer renderer(context());
  const RenderSettings settings = playback_settings();
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 4);
  move_cube(scene, -0.5f + 0.375f);  // (its left edge from -0.75 to -0.375: 6 pixels)
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 1);
  const float pixel = 4.0f / kSize;
  const RenderOutput out = renderer.read();
  const float behind = out.samples[pixel_at(-0.375 - 0.5 * pixel, 0.0)];
  const float farther = out.samples[pixel_at(-0.375 - 2.5 * pixel, 0.0)];
  std::printf("samples on the ground a pixel behind the outline %.0f, three pixels behind %.0f\n", behind, farther);
  EXPECT_GE(behind, 3.0f) << "history read where the outline was";
  EXPECT_EQ(farther, 1.0f) << "history there showed the cube: dropped";
}

// A mesh that deforms: its vertices move half the cube's move in the mesh,
// its instance the other half. The motion on its top is the whole move,
// from its vertices as from its transform, and the top finds itself in
// history; the next frame, with nothing changed, has no motion there.
TEST_F(TemporalTest, ReprojectionFollowsADeformingMeshsVertices) {
  GpuScene scene(context(), cube_over_ground());
  Renderer renderer(context());
  const RenderSettings settings = playback_settings();
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 4);
  std::vector<glm::vec3> shifted = scene.scene().meshes[0].positions;
  for (glm::vec3& p : shifted) p.x += 0.5f * kMove;
  scene.set_mesh_positions(0, shifted);
  move_cube(scene, -0.5f + 0.5f * kMove);
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 1);

  const glm::vec4 on_top = renderer.read_motion()[pixel_at(0.05, 0.05)];
  std::printf("motion on the deformed cube's top (%.4f, %.4f), depth %.3f\n", on_top.x, on_top.y, on_top.z);
  EXPECT_NEAR(on_top.x, -kMove * 0.5f, 1e-4f) << "half of it from the vertices, half from the instance";
  EXPECT_NEAR(on_top.y, 0.0f, 1e-4f);
  EXPECT_NEAR(on_top.z, 9.0f, 1e-3f);
  const float top = renderer.read().samples[pixel_at(0.05, 0.05)];
  std::printf("samples on the deformed cube's top: %.0f\n", top);
  EXPECT_GE(top, 2.0f) << "the deformed top found itself in history";

  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 1);
  const glm::vec4 after = renderer.read_motion()[pixel_at(0.05, 0.05)];
  EXPECT_NEAR(after.x, 0.0f, 1e-5f) << "the deformation is not counted again";
  EXPECT_NEAR(after.y, 0.0f, 1e-5f);
}

// The motion of an instance that turns and stretches: the cube turns a
// quarter about its centre and grows by half along its own x. Between two
// pixels of its top, the difference of their motions is the analytic one
// (the jitter moves both alike): a step dx across the screen was a step of
// (0, -dx) on the top a frame earlier, and a step dy one of (dy / 1.5, 0).
TEST_F(TemporalTest, ReprojectionFollowsACubeThatTurnsAndStretches) {
  GpuScene scene(context(), cube_over_ground());
  Renderer renderer(context());
  const RenderSettings settings = playback_settings();
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 1);
  const glm::mat4 turned = glm::translate(glm::mat4(1.0f), glm::vec3(-0.5f, 0, 0)) *
                           glm::rotate(glm::mat4(1.0f), float(M_PI / 2), glm::vec3(0, 0, 1)) *
                           glm::scale(glm::mat4(1.0f), glm::vec3(1.5f, 1.0f, 1.0f));
  scene.set_transforms({turned, glm::mat4(1.0f)});
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 1);

  const std::vector<glm::vec4> motion = renderer.read_motion();
  const double step = 4.0 / kSize;  // a pixel in world units
  // (the top view maps 4 units to 2 in NDC, whose y points down)
  auto in_world = [](glm::vec4 ndc) { return glm::vec2(2.0f * ndc.x, -2.0f * ndc.y); };
  const glm::vec4 at = motion[pixel_at(-0.5, 0.0)], right = motion[pixel_at(-0.5 + 2 * step, 0.0)];
  const glm::vec4 above = motion[pixel_at(-0.5, 3 * step)];
  const glm::vec2 across = in_world(right - at) / float(2 * step), up = in_world(above - at) / float(3 * step);
  std::printf("motion per unit across the top: (%.4f, %.4f), up it: (%.4f, %.4f); depth %.3f\n", across.x,
              across.y, up.x, up.y, at.z);
  EXPECT_NEAR(across.x, -1.0f, 1e-3f);
  EXPECT_NEAR(across.y, -1.0f, 1e-3f);
  EXPECT_NEAR(up.x, 1.0f / 1.5f, 1e-3f);
  EXPECT_NEAR(up.y, -1.0f, 1e-3f);
  EXPECT_NEAR(at.z, 9.0f, 1e-3f);
  EXPECT_EQ(at.w, 1.0f);
}

// A sheet striped three pixels wide (light and dark material slots), which
// casts no shadow, floats over the ground under a sun straight above, and
// slides along x by 0.37 of a pixel a step for 16 steps of one frame each:
// its last playback frame stays near a converged render of that pose.
// History is read again at each step; read bilinearly, its blur piled up
// step after step and washed the stripes out (0.28 of their contrast from
// the converged render, against 0.20 through the Catmull-Rom read; the
// engine sample's fins: docs/benchmarks.md). What is left is a kink's
// error: a box-filtered edge is no band-limited signal, and any
// interpolation of it errs by a few percent at each step.
TEST_F(TemporalTest, AMovingSurfacesFineDetailStaysSharpDuringPlayback) {
  constexpr float kPixel = 4.0f / kSize, kStripe = 3.0f * kPixel, kStep = 0.37f * kPixel;
  constexpr int kStripes = 12, kSteps = 16;
  Scene striped;
  Mesh stripes;
  for (int k = 0; k < kStripes; ++k) {
    const float x = -0.5f * kStripes * kStripe + k * kStripe;
    reference::append(stripes, reference::sheet({x, -0.6f}, {x + kStripe, 0.6f}, 0.5f));
    stripes.materials.insert(stripes.materials.end(), 2, uint32_t(k % 2));
  }
  striped.meshes = {stripes, reference::sheet({-20, -20}, {20, 20}, 0.0f)};
  Instance sheet{0, glm::mat4(1.0f), glm::vec3(0.8f)};
  sheet.materials = {Material{glm::vec3(0.9f)}, Material{glm::vec3(0.1f)}};
  sheet.casts_shadow = false;
  striped.instances = {sheet, {1, glm::mat4(1.0f), glm::vec3(0.8f)}};
  Light sun = tilted_sun();
  sun.direction = {0, 0, -1};
  auto at = [](float x) { return std::vector<glm::mat4>{glm::translate(glm::mat4(1.0f), glm::vec3(x, 0, 0)), glm::mat4(1.0f)}; };

  GpuScene scene(context(), striped);
  Renderer renderer(context());
  RenderSettings settings = playback_settings();
  settings.samples = 16;
  draw_top_view(renderer, scene, {sun}, glm::vec3(0.05f), settings, 16);
  for (int step = 1; step <= kSteps; ++step) {
    scene.set_transforms(at(step * kStep));
    draw_top_view(renderer, scene, {sun}, glm::vec3(0.05f), settings, 1);
  }
  const RenderOutput played = renderer.read();
  GpuScene fresh_scene(context(), striped);
  fresh_scene.set_transforms(at(kSteps * kStep));
  Renderer fresh(context());
  settings.temporal_reuse = false;
  settings.samples = 64;
  const RenderOutput expected = fresh.render(fresh_scene, top_view(), {sun}, glm::vec3(0.05f), kSize, kSize, settings);

  // The sheet's pixels two pixels in from its edges at its last pose.
  std::vector<size_t> inside;
  const float left = -0.5f * kStripes * kStripe + kSteps * kStep;
  for (size_t i = 0; i < expected.shadow.size(); ++i) {
    const double x = (double(i % kSize) + 0.5) / kSize * 4.0 - 2.0, y = 2.0 - (double(i / kSize) + 0.5) / kSize * 4.0;
    if (x > left + 2 * kPixel && x < left + kStripes * kStripe - 2 * kPixel && std::abs(y) < 0.6 - 2 * kPixel)
      inside.push_back(i);
  }
  double mean = 0.0;
  for (size_t i : inside) mean += brightness(expected, i) / double(inside.size());
  double contrast = 0.0, error = 0.0;
  for (size_t i : inside) {
    contrast += std::pow(brightness(expected, i) - mean, 2.0) / double(inside.size());
    error += std::pow(brightness(played, i) - brightness(expected, i), 2.0) / double(inside.size());
  }
  contrast = std::sqrt(contrast), error = std::sqrt(error);
  std::printf("stripes: %zu pixels, contrast (RMS about their mean) %.4f, last playback frame's RMS from a converged "
              "render %.4f (%.2f of the contrast)\n", inside.size(), contrast, error, error / contrast);
  ASSERT_GT(inside.size(), 300u);
  ASSERT_GT(contrast, 0.05) << "the stripes show at this size";
  EXPECT_LT(error, 0.24 * contrast) << "the stripes washed out during playback";
}

// A square flattened onto z = 0.5 (its transform scales z to 0, so it has no
// inverse) slides along x: its motion is its origin's, not NaN.
TEST_F(TemporalTest, AFlattenedInstanceMovesWithItsOrigin) {
  GpuScene scene(context(), cube_over_ground());
  auto flat_at = [](float x) {
    return glm::translate(glm::mat4(1.0f), glm::vec3(x, 0, 0.5f)) * glm::scale(glm::mat4(1.0f), glm::vec3(1, 1, 0));
  };
  scene.set_transforms({flat_at(-0.5f), glm::mat4(1.0f)});
  Renderer renderer(context());
  const RenderSettings settings = playback_settings();
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 1);
  scene.set_transforms({flat_at(-0.5f + kMove), glm::mat4(1.0f)});
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 1);

  const glm::vec4 on_square = renderer.read_motion()[pixel_at(0.05, 0.05)];
  std::printf("motion on the flattened square (%.4f, %.4f), depth %.3f\n", on_square.x, on_square.y, on_square.z);
  EXPECT_NEAR(on_square.x, -kMove * 0.5f, 1e-4f);
  EXPECT_NEAR(on_square.y, 0.0f, 1e-4f);
  EXPECT_NEAR(on_square.z, 9.5f, 1e-3f) << "the square's depth from the camera 10 above the ground";
}

// Playback: cube_over_ground's cube is placed at `moved` (from x = -0.5).
// Two frames later, where its old shadow lay and the sun now reaches, the
// image is as lit as a fresh render: no trail.
void expect_no_shadow_trail_after_two_frames(const glm::mat4& moved) {
  const vk::Context& context = testing::VulkanTest::context();
  GpuScene scene(context, cube_over_ground());
  Renderer renderer(context);
  RenderSettings settings = playback_settings();
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 8);
  const std::vector<float> before = renderer.read().shadow;
  scene.set_transforms({moved, glm::mat4(1.0f)});
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 2);
  const std::vector<float> played = renderer.read().shadow;

  // (a converged fresh render: the played frames' two new samples differ from
  // any fresh render's, so pixels at the new silhouette differ by their noise)
  GpuScene fresh_scene(context, cube_over_ground());
  fresh_scene.set_transforms({moved, glm::mat4(1.0f)});
  Renderer fresh(context);
  settings.temporal_reuse = false;
  settings.samples = 64;
  const std::vector<float> expected =
      fresh.render(fresh_scene, top_view(), {tilted_sun()}, glm::vec3(0.05f), kSize, kSize, settings).shadow;
  double worst = 0.0, darker = 0.0;
  int count = 0;
  for (size_t i = 0; i < expected.size(); ++i)
    if (before[i] < 0.3f && expected[i] > 0.9f) {
      worst = std::max(worst, double(std::abs(played[i] - expected[i])));
      darker += expected[i] - played[i];
      ++count;
    }
  darker /= std::max(count, 1);
  std::printf("old shadow now lit: %d pixels, played darker than fresh by %.4f on average, largest |played - fresh| "
              "%.3f\n", count, darker, worst);
  ASSERT_GT(count, 20);
  EXPECT_LT(darker, 0.02) << "the moved cube's old shadow is gone after two frames";
  EXPECT_LT(worst, 0.25) << "no pixel keeps much of the old shadow";
}

// The cube moves by its own width: its shadow, followed to where it was
// (follow_shadow), leaves none behind.
TEST_F(TemporalTest, MovingCasterLeavesNoShadowTrailAfterTwoFrames) {
  expect_no_shadow_trail_after_two_frames(glm::translate(glm::mat4(1.0f), glm::vec3(-0.5f + kMove, 0, 0)));
}

// The cube swings a quarter turn about a point beside it, and stretches:
// follow_shadow's estimate of
// where each shadow point was is then not exact (the middle of the light's
// path through the cube's box), and the resolve's choice and clip keep the
// old shadow from lingering.
TEST_F(TemporalTest, ATurnedCasterLeavesNoShadowTrailAfterTwoFrames) {
  const glm::vec3 pivot(-0.5f, 0.75f, 0.0f);
  expect_no_shadow_trail_after_two_frames(glm::translate(glm::mat4(1.0f), pivot) *
                                          glm::rotate(glm::mat4(1.0f), float(M_PI / 2), glm::vec3(0, 0, 1)) *
                                          glm::scale(glm::mat4(1.0f), glm::vec3(1.5f, 1.0f, 1.0f)) *
                                          glm::translate(glm::mat4(1.0f), glm::vec3(-0.5f, 0, 0) - pivot));
}

// The first frame after a move, under a still camera, shades only the
// tiles where the keep pass left pixels (shaders/kept_tiles.glsl.h): in an
// image whose size is no multiple of the tiles, every pixel is shaded or
// kept (a tile left out keeps a mean of no samples: with the partial tiles
// at the right edge left out of the list, the fewest samples were 0), and
// the moved shadow reaching into the partial tiles at the right and bottom
// edges is drawn there in that one frame.
TEST_F(TemporalTest, APlaybackFrameShadesThePartialTilesAtTheImageEdges) {
  constexpr int kWidth = 70, kHeight = 46;  // (8 x 8 tiles: 6 columns and 6 rows over)
  const glm::mat4 moved = glm::translate(glm::mat4(1.0f), glm::vec3(1.2f, -1.6f, 0.0f));
  GpuScene scene(context(), cube_over_ground());
  Renderer renderer(context());
  RenderSettings settings = playback_settings();
  settings.samples = 8;
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, settings.samples, {kWidth, kHeight});
  const std::vector<float> before = renderer.read().shadow;
  scene.set_transforms({moved, glm::mat4(1.0f)});
  draw_top_view(renderer, scene, {tilted_sun()}, glm::vec3(0.05f), settings, 1, {kWidth, kHeight});
  const RenderOutput out = renderer.read();
  const std::vector<float>& played = out.shadow;
  // (every pixel was shaded or kept: its mean stands for a sample at least)
  float fewest_samples = 1e30f;
  for (float samples : out.samples) fewest_samples = std::min(fewest_samples, samples);

  GpuScene fresh_scene(context(), cube_over_ground());
  fresh_scene.set_transforms({moved, glm::mat4(1.0f)});
  Renderer fresh(context());
  settings.temporal_reuse = false;
  settings.samples = 32;
  const std::vector<float> expected =
      fresh.render(fresh_scene, top_view(), {tilted_sun()}, glm::vec3(0.05f), kWidth, kHeight, settings).shadow;
  // The pixels of the partial tiles (the last columns and rows) that the move darkened.
  int count = 0;
  double worst = 0.0;
  for (size_t i = 0; i < expected.size(); ++i) {
    const bool edge = int(i % kWidth) >= 64 || int(i / kWidth) >= 40;
    if (!edge || before[i] < 0.9f || expected[i] > 0.3f) continue;
    ++count;
    worst = std::max(worst, double(std::abs(played[i] - expected[i])));
  }
  std::printf("edge tiles the moved shadow reached: %d pixels, largest |played - fresh| %.3f; fewest samples %.0f\n",
              count, worst, fewest_samples);
  EXPECT_GE(fewest_samples, 1.0f);
  ASSERT_GT(count, 20);
  EXPECT_LT(worst, 0.3) << "the moved shadow is drawn in the partial tiles in its first frame";
  // The keep pass's time is given apart, as a part of the temporal passes'
  // (none where the device has no timestamps).
  const RenderTimings& timings = renderer.timings();
  if (timings.temporal_gpu_ms > 0.0) {
    EXPECT_GT(timings.keep_gpu_ms, 0.0);
    EXPECT_LT(timings.keep_gpu_ms, timings.temporal_gpu_ms) << "the resolve's share is the rest";
  }
}

// The pixels on a dark cube's silhouette against what lies behind it
// (`behind`: a depth), rendered still, then played back as the cube moves
// out of the view and four frames change nothing: the largest difference
// (red) from a fresh render without the cube, and how many such pixels.
struct OldSilhouette {
  int count = 0;
  double worst = 0.0;
};
template <class Behind>
OldSilhouette old_silhouette(const Camera& camera, glm::vec3 sky, Behind behind, bool cube_casts_shadow = true) {
  Scene scene_before = cube_over_ground();
  scene_before.instances[0].base_color = glm::vec3(0.02f);  // a dark cube over a light ground: a ghost shows
  scene_before.instances[0].casts_shadow = cube_casts_shadow;
  Light sun = tilted_sun();
  sun.direction = glm::normalize(glm::vec3(0.0f, -1.0f, -1.0f));  // from beyond the far ground
  const float moved_x = 3.0f;  // out of the view
  RenderSettings settings = playback_settings();
  settings.samples = 8;
  const vk::Context& context = testing::VulkanTest::context();

  GpuScene scene(context, scene_before);
  Renderer renderer(context);
  renderer.begin(scene, camera, {sun}, sky, kSize, kSize, settings, true);
  for (int frame = 0; frame < settings.samples; ++frame) renderer.add_frame();
  const RenderOutput before = renderer.read();
  // Playback: the cube moves away, then frame changes that move nothing.
  move_cube(scene, moved_x);
  for (int step = 0; step < 4; ++step) {
    renderer.begin(scene, camera, {sun}, sky, kSize, kSize, settings, true);
    renderer.add_frame();
  }
  const RenderOutput played = renderer.read();

  GpuScene fresh_scene(context, scene_before);
  move_cube(fresh_scene, moved_x);
  Renderer fresh(context);
  RenderSettings still = settings;
  still.temporal_reuse = false;
  still.samples = 32;
  const RenderOutput expected = fresh.render(fresh_scene, camera, {sun}, sky, kSize, kSize, still);
  OldSilhouette result;
  for (int y = 1; y + 1 < kSize; ++y)
    for (int x = 1; x + 1 < kSize; ++x) {
      const size_t i = size_t(y) * kSize + size_t(x);
      bool cube = false, behind_it = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const float depth = before.depth[size_t(y + dy) * kSize + size_t(x + dx)];
          cube = cube || depth < 4.0f;
          behind_it = behind_it || behind(depth);
        }
      if (!(cube && behind_it) || !behind(expected.depth[i])) continue;
      ++result.count;
      result.worst = std::max(result.worst, double(std::abs(played.combined[4 * i] - expected.combined[4 * i])));
    }
  return result;
}

// A silhouette pixel's history holds both surfaces its samples saw (the
// object's edge and the ground far behind it). When the object moves away,
// the ground that now shows matches the far end of that history's depths,
// but the history still mixes in the object: it must not be kept as the
// settled value of a still pixel (the ground far behind is nowhere near
// what moved), or the old silhouette stays on screen for good.
TEST_F(TemporalTest, AMovedObjectLeavesNoSilhouetteBehind) {
  Camera camera;  // low, looking along +y past the cube at ground 4 to 20 units behind it
  camera.world_to_view = glm::lookAt(glm::vec3(-0.5f, -3.0f, 1.0f), glm::vec3(-0.5f, 10.0f, 0.0f), glm::vec3(0, 0, 1));
  camera.projection = glm::perspectiveRH_NO(0.6f, 1.0f, 0.1f, 40.0f);
  const OldSilhouette ground = old_silhouette(camera, glm::vec3(0.0f), [](float d) { return d > 6.0f && d < 1e9f; });
  std::printf("old silhouette pixels: %d, largest |played - fresh| (red) %.3f\n", ground.count, ground.worst);
  ASSERT_GT(ground.count, 10);
  EXPECT_LT(ground.worst, 0.1) << "the moved cube's old silhouette is gone after four frames";
}

// The same for an object whose shadows are off: it is in no field and
// shadows nothing, but it moved on screen all the same. (The box of what
// moved had held the shadow casters only, and this cube's old silhouette
// settled for good: 0.203.)
TEST_F(TemporalTest, AMovedObjectThatCastsNoShadowLeavesNoSilhouette) {
  Camera camera;
  camera.world_to_view = glm::lookAt(glm::vec3(-0.5f, -3.0f, 1.0f), glm::vec3(-0.5f, 10.0f, 0.0f), glm::vec3(0, 0, 1));
  camera.projection = glm::perspectiveRH_NO(0.6f, 1.0f, 0.1f, 40.0f);
  const OldSilhouette ground =
      old_silhouette(camera, glm::vec3(0.0f), [](float d) { return d > 6.0f && d < 1e9f; }, false);
  std::printf("old silhouette pixels: %d, largest |played - fresh| (red) %.3f\n", ground.count, ground.worst);
  ASSERT_GT(ground.count, 10);
  EXPECT_LT(ground.worst, 0.1) << "the moved cube's old silhouette is gone after four frames";
}

// The same against the sky: a background pixel's history near the old
// outline holds the cube too, and is not kept either.
TEST_F(TemporalTest, AMovedObjectLeavesNoSilhouetteOnTheSky) {
  Camera camera;  // level with the cube's top, looking a little up: the cube against the sky
  camera.world_to_view = glm::lookAt(glm::vec3(-0.5f, -3.0f, 0.9f), glm::vec3(-0.5f, 10.0f, 2.5f), glm::vec3(0, 0, 1));
  camera.projection = glm::perspectiveRH_NO(0.6f, 1.0f, 0.1f, 40.0f);
  const OldSilhouette sky = old_silhouette(camera, glm::vec3(0.6f), [](float d) { return d > 1e9f; });
  std::printf("old silhouette pixels on the sky: %d, largest |played - fresh| (red) %.3f\n", sky.count, sky.worst);
  ASSERT_GT(sky.count, 10);
  EXPECT_LT(sky.worst, 0.1) << "the moved cube's old outline is gone from the sky after four frames";
}

// The cube moves across the sky in eight steps, a frame each (as playback
// draws), then stays: no pixel of the sky keeps any of its colour. A sky
// pixel beside the moving outline reads history where the outline was,
// and its history's depths move as the outline's did: moved by the sky's
// (none), not by its empty motion in the G-buffer, or they lay 1e10 behind
// the camera, and after the outline had gone the sky settled on the cube's
// colour for good, one dot a step (0.59 off).
TEST_F(TemporalTest, AnObjectMovingAcrossTheSkyLeavesNoTrail) {
  Camera camera;  // as AMovedObjectLeavesNoSilhouetteOnTheSky's
  camera.world_to_view = glm::lookAt(glm::vec3(-0.5f, -3.0f, 0.9f), glm::vec3(-0.5f, 10.0f, 2.5f), glm::vec3(0, 0, 1));
  camera.projection = glm::perspectiveRH_NO(0.6f, 1.0f, 0.1f, 40.0f);
  Scene scene_before = cube_over_ground();
  scene_before.instances[0].base_color = glm::vec3(0.02f);
  Light sun = tilted_sun();
  sun.direction = glm::normalize(glm::vec3(0.0f, -1.0f, -1.0f));
  const glm::vec3 sky(0.6f);
  RenderSettings settings = playback_settings();
  settings.samples = 8;
  GpuScene scene(context(), scene_before);
  Renderer renderer(context());
  renderer.begin(scene, camera, {sun}, sky, kSize, kSize, settings, true);
  for (int frame = 0; frame < settings.samples; ++frame) renderer.add_frame();
  const float last_x = -0.5f + 8 * 0.08f;
  for (int step = 1; step <= 12; ++step) {  // (eight steps, then four frame changes that move nothing)
    move_cube(scene, -0.5f + float(std::min(step, 8)) * 0.08f);
    renderer.begin(scene, camera, {sun}, sky, kSize, kSize, settings, true);
    renderer.add_frame();
  }
  const RenderOutput played = renderer.read();
  GpuScene fresh_scene(context(), scene_before);
  move_cube(fresh_scene, last_x);
  Renderer fresh(context());
  RenderSettings still = settings;
  still.temporal_reuse = false;
  const RenderOutput expected = fresh.render(fresh_scene, camera, {sun}, sky, kSize, kSize, still);
  int sky_pixels = 0;
  double worst = 0.0;
  float nearest_on_sky = 1e30f;  // (the Depth pass: the nearest any of a pixel's samples saw)
  for (int y = 1; y + 1 < kSize; ++y)
    for (int x = 1; x + 1 < kSize; ++x) {
    bool clear = true;  // (sky around it too: the cube's outline where it stopped is left out)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) clear = clear && expected.depth[size_t(y + dy) * kSize + size_t(x + dx)] >= 1e9f;
    if (!clear) continue;
    const size_t i = size_t(y) * kSize + size_t(x);
    ++sky_pixels;
    worst = std::max(worst, double(std::abs(played.combined[4 * i] - expected.combined[4 * i])));
    nearest_on_sky = std::min(nearest_on_sky, played.depth[i]);
    }
  std::printf("sky pixels %d, largest |played - fresh| (red) %.3f, nearest depth seen there %g\n", sky_pixels, worst,
              nearest_on_sky);
  ASSERT_GT(sky_pixels, 100);
  EXPECT_LT(worst, 0.05) << "the sky along the cube's way keeps none of it";
  EXPECT_GT(nearest_on_sky, 0.0f) << "its history's depths in front of the camera";
}

// A thin dark bar lying on the ground (a stem on its wall), a centimetre
// high and narrower than a pixel, seen from above: its pixels' history holds
// the bar and the ground at depths closer than any tolerance can tell apart.
// When the bar moves away, that history must not pass for the ground's and
// settle (IvyGen's stems stayed on their wall in the viewport): the instances
// its samples saw tell that it held the bar.
TEST_F(TemporalTest, AThinThingMovedOffASurfaceLeavesNoImageOnIt) {
  Scene scene_before;
  scene_before.meshes = {reference::box({-1.2f, -0.015f, 0.002f}, {1.2f, 0.015f, 0.012f}),
                         reference::sheet({-20, -20}, {20, 20}, 0.0f)};
  scene_before.instances = {{0, glm::mat4(1.0f), glm::vec3(0.02f)}, {1, glm::mat4(1.0f), glm::vec3(0.8f)}};
  const Light sun = tilted_sun();
  RenderSettings settings = playback_settings();
  settings.samples = 8;
  const vk::Context& context = testing::VulkanTest::context();
  GpuScene scene(context, scene_before);
  Renderer renderer(context);
  draw_top_view(renderer, scene, {sun}, glm::vec3(0.0f), settings, settings.samples);
  const RenderOutput before = renderer.read();
  const glm::mat4 away = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 3.0f, 0.0f));  // out of the view
  scene.set_transforms({away, glm::mat4(1.0f)});
  for (int step = 0; step < 4; ++step) draw_top_view(renderer, scene, {sun}, glm::vec3(0.0f), settings, 1);
  const RenderOutput played = renderer.read();

  GpuScene fresh_scene(context, scene_before);
  fresh_scene.set_transforms({away, glm::mat4(1.0f)});
  Renderer fresh(context);
  RenderSettings still = settings;
  still.temporal_reuse = false;
  still.samples = 16;
  const RenderOutput expected = fresh.render(fresh_scene, top_view(), {sun}, glm::vec3(0.0f), kSize, kSize, still);
  int bar_pixels = 0;
  double worst = 0.0;
  for (size_t i = 0; i < size_t(kSize) * kSize; ++i) {
    if (brightness(before, i) > 0.9f * brightness(expected, i)) continue;  // (where the bar showed)
    ++bar_pixels;
    worst = std::max(worst, double(std::abs(brightness(played, i) - brightness(expected, i))));
  }
  std::printf("bar pixels: %d, largest |played - fresh| %.3f\n", bar_pixels, worst);
  ASSERT_GT(bar_pixels, 20);
  EXPECT_LT(worst, 0.05) << "the moved bar's image is gone from the ground after four frames";
}

// Playback of a still scene, one frame per frame change: the samples carried
// over and the new ones must differ (each frame goes on through the jitter
// sequences), so 16 such frames come about as close to the converged image as
// 16 frames accumulated without a change, not stuck at the first sample.
TEST_F(TemporalTest, PlaybackFramesOfAStillSceneConvergeLikeAnAccumulation) {
  const Light sun = wide_sun();  // (most of the noise is in its penumbra)
  auto shadow_of = [&](int samples) {
    GpuScene scene(context(), cube_over_ground());
    Renderer renderer(context());
    RenderSettings settings = playback_settings();
    settings.temporal_reuse = false;
    settings.samples = samples;
    return renderer.render(scene, top_view(), {sun}, glm::vec3(0.05f), kSize, kSize, settings).shadow;
  };
  const std::vector<float> converged = shadow_of(128), single = shadow_of(1), accumulated = shadow_of(16);

  GpuScene scene(context(), cube_over_ground());
  Renderer renderer(context());
  const RenderSettings settings = playback_settings();
  for (int frame = 0; frame < 16; ++frame) {
    move_cube(scene, -0.5f);  // (the same place: a frame change that moved nothing)
    renderer.begin(scene, top_view(), {sun}, glm::vec3(0.05f), kSize, kSize, settings, true);
    renderer.add_frame();
  }
  const std::vector<float> played = renderer.read().shadow;
  auto rms = [&](const std::vector<float>& image) {
    double sum = 0.0;
    for (size_t i = 0; i < image.size(); ++i) sum += double(image[i] - converged[i]) * (image[i] - converged[i]);
    return std::sqrt(sum / double(image.size()));
  };
  std::printf("shadow RMS from 128 frames: 1 frame %.4f, 16 accumulated %.4f, 16 playback frames %.4f\n", rms(single),
              rms(accumulated), rms(played));
  ASSERT_GT(rms(single), 2.0 * rms(accumulated)) << "the scene's single frames are noisy enough to tell";
  EXPECT_LT(rms(played), 0.6 * rms(single));
  EXPECT_LT(rms(played), 1.5 * rms(accumulated));
}

// A still cube's soft shadow beside a cube that moves: once the still scene
// has converged, playback frames leave the still shadow's pixels exactly as
// they were (they are settled: no new jittered sample makes them shimmer),
// while the moving cube's shadow follows it.
TEST_F(TemporalTest, SettledPixelsDoNotShimmerDuringPlayback) {
  Light sun = wide_sun();
  GpuScene scene(context(), two_cubes(1.0f, -1.0f));
  Renderer renderer(context());
  RenderSettings settings = playback_settings();
  settings.samples = 8;
  draw_top_view(renderer, scene, {sun}, glm::vec3(0.05f), settings, settings.samples);
  std::vector<std::vector<float>> frames;
  for (int step = 1; step <= 3; ++step) {
    scene.set_transforms(two_cubes_at(-0.5f + 0.1f * float(step), 1.0f, -1.0f));
    renderer.begin(scene, top_view(), {sun}, glm::vec3(0.05f), kSize, kSize, settings, true);
    renderer.add_frame();
    frames.push_back(renderer.read().shadow);
  }
  // The still cube's penumbra (y near -1, beyond the cube's far edge along +x), and the moving one's.
  double still_change = 0.0, moving_change = 0.0, penumbra = 0.0;
  for (double x = 0.1; x <= 1.0; x += 4.0 / kSize)
    for (double y = -1.4; y <= -0.6; y += 4.0 / kSize) {
      const size_t i = pixel_at(x, y), j = pixel_at(x, y + 2.0);
      penumbra = std::max(penumbra, double(std::min(frames[0][i], 1.0f - frames[0][i])));
      for (size_t f = 1; f < frames.size(); ++f) {
        still_change = std::max(still_change, double(std::abs(frames[f][i] - frames[f - 1][i])));
        moving_change = std::max(moving_change, double(std::abs(frames[f][j] - frames[f - 1][j])));
      }
    }
  std::printf("largest change between playback frames: still shadow %.6f, moving shadow %.3f\n", still_change,
              moving_change);
  ASSERT_GT(penumbra, 0.2) << "the still shadow has a penumbra to shimmer";
  EXPECT_EQ(still_change, 0.0);
  EXPECT_GT(moving_change, 0.2) << "the moving cube's shadow moved";

  // A turned sun moves every shadow: nothing is settled then.
  sun.direction = glm::vec3(0.5f, 0.3f, -0.8f);
  draw_top_view(renderer, scene, {sun}, glm::vec3(0.05f), settings, 1);
  const std::vector<float> turned = renderer.read().shadow;
  double turned_change = 0.0;
  for (double x = 0.1; x <= 1.0; x += 4.0 / kSize)
    for (double y = -1.4; y <= -0.6; y += 4.0 / kSize)
      turned_change = std::max(turned_change, double(std::abs(turned[pixel_at(x, y)] - frames.back()[pixel_at(x, y)])));
  EXPECT_GT(turned_change, 0.2) << "the still cube's shadow follows the sun";
}

// A still receiver near what moved (within the moved box's size, beyond its
// contact): only the sky it sees can change, by the moved object's share of
// its hemisphere, and slowly. It is settled: it keeps its converged value
// and its count, and is not shaded during playback (temporal_keep.comp).
// When it took each frame's new sample with its weight instead, that
// sample's noise showed from frame to frame more than its sky's change did.
TEST_F(TemporalTest, AStillPixelBeyondContactWithWhatMovedStaysAsItWas) {
  Light sun = wide_sun();
  GpuScene scene(context(), two_cubes(0.5f, -0.5f));
  RenderSettings settings = playback_settings();
  settings.samples = 8;
  settings.quick_first_frame = true;  // (as the viewport: the frame after a change shares the quads' visibility)
  const glm::vec3 sky(1.5f);  // (a bright sky: its two cones a frame are the noisiest part)
  sun.energy = 1.0f;
  // The still cube's shadow (y from -0.7 to -0.3, beyond its far edge along
  // +x), 0.55 to 0.95 from the moving cube's box; and the moving one's.
  std::vector<size_t> still_shadow, moving_shadow;
  for (double x = 0.1; x <= 1.0; x += 4.0 / kSize)
    for (double y = -0.7; y <= -0.3; y += 4.0 / kSize) {
      still_shadow.push_back(pixel_at(x, y));
      moving_shadow.push_back(pixel_at(x, y + 1.0));
    }

  Renderer renderer(context());
  draw_top_view(renderer, scene, {sun}, sky, settings, settings.samples);
  RenderOutput previous = renderer.read();
  const double noise = one_sample_noise(scene, {sun}, sky, settings, previous, still_shadow);

  double near_change = 0.0, moving_change = 0.0;
  float most_samples = 0.0f;  // (of the still shadow's pixels, after the last step)
  const int steps = 4;
  for (int step = 1; step <= steps; ++step) {
    scene.set_transforms(two_cubes_at(-0.5f + 0.05f * float(step), 0.5f, -0.5f));
    draw_top_view(renderer, scene, {sun}, sky, settings, 1);
    const RenderOutput out = renderer.read();
    near_change = std::max(near_change, mean_change(out, previous, still_shadow));
    moving_change = std::max(moving_change, mean_change(out, previous, moving_shadow));
    most_samples = 0.0f;
    for (size_t i : still_shadow) most_samples = std::max(most_samples, out.samples[i]);
    previous = out;
  }
  std::printf("mean change between playback frames: still shadow near the moving cube %.5f (a sample's noise %.4f), "
              "moving shadow %.4f; the still shadow's history after %d steps: up to %.0f samples\n", near_change, noise,
              moving_change, steps, most_samples);
  // Its count stays the still accumulation's (history_samples), as does its value.
  EXPECT_EQ(most_samples, float(settings.samples));
  ASSERT_GT(noise, 0.01) << "one sample is noisy there";
  EXPECT_EQ(near_change, 0.0) << "a new sample's noise would show there";
  EXPECT_GT(moving_change, 0.02) << "the moving cube's shadow moved";
}

// A still pixel in contact with what moved (within kContactReach of its
// box) is shaded anew each playback frame: its sky may change fast. Where
// nothing there changed beyond the samples' noise (the clip holds history),
// it keeps its converged value. Here: the ground beside a cube lowered to
// 0.05 above it, under a sky alone, as the cube slides along x: 108 of 144
// pixel steps kept their value (101 with the noise judged over the 3x3
// pixels around each, not samples a quad apart; with each frame's sample
// blended in, a mutation run, none did).
// The accumulation keeps its samples' second moments beside their means
// (the temporal resolve judges a still pixel's noise by them): after N
// frames, each pixel's are the mean of its N samples' Y, Co and Cg squared. Each sample is read back from the running means (N m_N -
// (N - 1) m_(N-1)). Where the cube moved, history carries them on: a
// pixel far from it keeps its own.
TEST_F(TemporalTest, TheAccumulationKeepsItsSamplesSecondMoments) {
  GpuScene scene(context(), cube_over_ground());
  RenderSettings settings = playback_settings();
  settings.samples = 8;
  const std::vector<Light> lights = {wide_sun()};
  const glm::vec3 sky(0.6f);
  Renderer renderer(context());
  renderer.begin(scene, top_view(), lights, sky, kSize, kSize, settings, true);
  const size_t pixels = size_t(kSize) * kSize;
  std::vector<glm::vec3> expected(pixels, glm::vec3(0.0f)), previous_mean(pixels, glm::vec3(0.0f));
  for (int n = 1; n <= settings.samples; ++n) {
    renderer.add_frame();
    const RenderOutput out = renderer.read();
    for (size_t i = 0; i < pixels; ++i) {
      const glm::vec3 mean(out.combined[4 * i], out.combined[4 * i + 1], out.combined[4 * i + 2]);
      const glm::vec3 sample = float(n) * mean - float(n - 1) * previous_mean[i];
      const glm::vec3 ycocg(0.25f * sample.r + 0.5f * sample.g + 0.25f * sample.b, 0.5f * (sample.r - sample.b),
                            -0.25f * sample.r + 0.5f * sample.g - 0.25f * sample.b);
      expected[i] += (ycocg * ycocg - expected[i]) / float(n);
      previous_mean[i] = mean;
    }
  }
  const std::vector<glm::vec4> moments = renderer.read_sample_moments();
  ASSERT_EQ(moments.size(), pixels);
  const RenderOutput converged = renderer.read();
  double worst = 0.0;
  size_t noisy = 0;
  for (size_t i = 0; i < pixels; ++i) {
    for (int c = 0; c < 3; ++c) worst = std::max(worst, double(std::abs(moments[i][c] - expected[i][c])));
    const float luma = 0.25f * converged.combined[4 * i] + 0.5f * converged.combined[4 * i + 1] +
                       0.25f * converged.combined[4 * i + 2];
    if (moments[i].x - luma * luma > 1e-3f) ++noisy;
  }
  std::printf("second moments after %d samples: worst difference %.2e; %zu pixels with a noise spread\n",
              settings.samples, worst, noisy);
  EXPECT_GT(noisy, pixels / 20) << "the penumbrae and the sky are noisy";
  EXPECT_LT(worst, 2e-3);

  // The cube moves a little: the ground's far corner is kept from history, and so are its moments.
  const size_t far = pixel_at(1.8, 1.8);
  move_cube(scene, -0.45f);
  draw_top_view(renderer, scene, lights, sky, settings, 1);
  EXPECT_EQ(renderer.read().samples[far], float(settings.samples)) << "kept from history";
  EXPECT_EQ(renderer.read_sample_moments()[far], moments[far]);
}

TEST_F(TemporalTest, AStillPixelInContactWithWhatMovedKeepsItsValueWhereNothingChanged) {
  auto cube_at = [](float x) {
    return std::vector<glm::mat4>{glm::translate(glm::mat4(1.0f), glm::vec3(x, 0, -0.45f)), glm::mat4(1.0f)};
  };
  Scene lowered = cube_over_ground();
  lowered.instances[0].object_to_world = cube_at(-0.5f)[0];
  GpuScene scene(context(), lowered);
  RenderSettings settings = playback_settings();
  settings.samples = 8;
  settings.quick_first_frame = true;
  const glm::vec3 sky(1.5f);
  // The ground 0.12 to 0.15 from the cube's sides (y = +-0.25), along them:
  // within contact reach of the moved box, beyond the jitter's reach (2
  // pixels) of the cube's outline.
  std::vector<size_t> contact;
  for (double x = -0.75; x <= -0.25; x += 4.0 / kSize)
    for (double y : {-0.4, -0.375, 0.375, 0.4}) contact.push_back(pixel_at(x, y));

  Renderer renderer(context());
  draw_top_view(renderer, scene, {}, sky, settings, settings.samples);
  RenderOutput previous = renderer.read();
  const double noise = one_sample_noise(scene, {}, sky, settings, previous, contact);
  size_t kept = 0, seen = 0;
  for (int step = 1; step <= 4; ++step) {
    scene.set_transforms(cube_at(-0.5f + 0.05f * float(step)));
    draw_top_view(renderer, scene, {}, sky, settings, 1);
    const RenderOutput out = renderer.read();
    for (size_t i : contact) kept += brightness(out, i) == brightness(previous, i) ? 1 : 0;
    seen += contact.size();
    previous = out;
  }
  std::printf("beside the moving cube: %zu of %zu pixel steps kept their value (a sample's noise there %.4f)\n", kept,
              seen, noise);
  ASSERT_GT(noise, 0.01) << "one sample is noisy there";
  // (Near the cube's ends its contact shadow does change: there the clip moves history.)
  EXPECT_GE(double(kept), 0.5 * double(seen)) << "a new sample's noise shows there";
}

namespace {
// A camera looking down at the ground at a slant from behind the cube (no
// far plane: the projection the add-on gives a Blender camera).
const glm::vec3 kSlantedEye(0, -7, 2.5f), kSlantedTarget(0, 0, 0.5f);
Camera slanted_view() {
  Camera camera;
  camera.world_to_view = glm::lookAt(kSlantedEye, kSlantedTarget, glm::vec3(0, 0, 1));
  camera.projection = glm::infinitePerspectiveRH(0.8f, 1.0f, 0.1f);
  return camera;
}

// Converges `renderer` (kConvergedSamples) on `scene` seen by `camera`,
// moves the cube, and draws the first frame after the move.
constexpr int kConvergedSamples = 4;
void converge_then_move_cube(Renderer& renderer, GpuScene& scene, const Camera& camera) {
  RenderSettings settings = playback_settings();
  settings.samples = kConvergedSamples;
  renderer.begin(scene, camera, {tilted_sun()}, glm::vec3(0.05f), kSize, kSize, settings, true);
  for (int frame = 0; frame < settings.samples; ++frame) renderer.add_frame();
  move_cube(scene, -0.45f);
  renderer.begin(scene, camera, {tilted_sun()}, glm::vec3(0.05f), kSize, kSize, settings, true);
  renderer.add_frame();
}
}  // namespace

// A viewport's playback frame (objects moved, the camera stayed, history
// converged) is drawn at the pixel centres: where history was dropped its
// one sample is what shows, and a centred one lies nearer the filtered
// pixel. The G-buffer's depth of each ground pixel is then that of the ray
// through the pixel's centre; the frame after it is jittered again.
TEST_F(TemporalTest, APlaybackFrameIsDrawnAtThePixelCentres) {
  GpuScene scene(context(), cube_over_ground());
  const Camera camera = slanted_view();  // (depth changes across each ground pixel)
  Renderer renderer(context());
  converge_then_move_cube(renderer, scene, camera);
  const std::vector<glm::vec4> playback = renderer.read_motion();
  renderer.add_frame();
  const std::vector<glm::vec4> next = renderer.read_motion();

  // The depth along the view of the ground (z = 0) through a pixel's centre (rows top to bottom).
  const glm::mat4 clip_to_world = glm::inverse(camera.projection * camera.world_to_view);
  const glm::vec3 eye = kSlantedEye, forward = glm::normalize(kSlantedTarget - kSlantedEye);
  auto centre_depth = [&](int x, int y) {
    const glm::vec2 ndc((float(x) + 0.5f) / kSize * 2.0f - 1.0f, 1.0f - (float(y) + 0.5f) / kSize * 2.0f);
    const glm::vec4 far_point = clip_to_world * glm::vec4(ndc, 0.5f, 1.0f);
    const glm::vec3 ray = glm::normalize(glm::vec3(far_point) / far_point.w - eye);
    return glm::dot(ray * (-eye.z / ray.z), forward);
  };
  double worst_playback = 0.0, most_next = 0.0;
  int ground = 0;
  for (int y = kSize / 2; y < kSize; y += 3)  // (the near half of the image: ground, away from the cube)
    for (int x = 2; x < kSize / 4; x += 3) {
      const size_t i = size_t(y) * kSize + size_t(x);
      if (playback[i].w != 1.0f) continue;
      const float expected = centre_depth(x, y);
      worst_playback = std::max(worst_playback, double(std::abs(playback[i].z - expected) / expected));
      most_next = std::max(most_next, double(std::abs(next[i].z - expected) / expected));
      ground++;
    }
  std::printf("ground pixels %d: depth off the pixel centre's by up to %.2e (playback frame), %.2e (the next frame)\n",
              ground, worst_playback, most_next);
  ASSERT_GT(ground, 20);
  EXPECT_LT(worst_playback, 1e-4);
  EXPECT_GT(most_next, 1e-3) << "the frames after it are jittered";
}

// The background behind a still camera settles as the still surfaces do:
// its motion comes from a matrix made in double precision, the identity
// where the camera stayed. (Through an inverse in single precision it was a
// thousandth of a pixel off, and the horizon's pixels, half ground and half
// sky, took each new jittered sample and flickered during playback.)
TEST_F(TemporalTest, TheBackgroundSettlesBehindAStillCamera) {
  Scene scene_data = cube_over_ground();
  scene_data.meshes[1] = reference::sheet({-3, -3}, {3, 3}, 0.0f);  // (a ground that ends: sky above its far edge)
  GpuScene scene(context(), scene_data);
  Renderer renderer(context());
  converge_then_move_cube(renderer, scene, slanted_view());
  const RenderOutput out = renderer.read();
  // The left and right quarters of the image, far from the cube in the middle.
  int background = 0, edge = 0, unsettled = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      if (std::abs(x - kSize / 2) < kSize / 4) continue;
      const size_t i = size_t(y) * kSize + size_t(x);
      const bool sky = out.combined[4 * i + 3] == 0.0f;
      const bool beside_ground = y + 1 < kSize && out.combined[4 * (i + kSize) + 3] > 0.0f;
      if (!sky) continue;
      background++;
      if (beside_ground) edge++;
      if (out.samples[i] != float(kConvergedSamples)) unsettled++;
    }
  std::printf("background pixels beside the cube: %d (%d on the horizon), not settled: %d\n", background, edge,
              unsettled);
  ASSERT_GT(edge, 10) << "the ground's far edge is in view";
  EXPECT_EQ(unsettled, 0);
}

// A block standing on a slab (one mesh) casts a wide sun's noisy penumbra
// on the slab. The mesh moves along x, a step at a time: the penumbra moves
// with it, so the slab's history holds (the shadow moved with its surface),
// and where one sample's noise is the only difference, history keeps its
// samples; tested as a moved shadow, the noise restarted it at almost
// every step. Under a point light that moves the penumbra over the slab,
// the same steps restart it.
Scene block_on_slab() {
  Scene scene;
  Mesh step = reference::box({-1.0f, -0.5f, 0.3f}, {1.0f, 0.5f, 0.4f});
  reference::append(step, reference::box({-0.2f, -0.5f, 0.4f}, {0.2f, 0.5f, 0.9f}));
  scene.meshes = {step, reference::sheet({-20, -20}, {20, 20}, 0.0f)};
  scene.instances = {{0, glm::mat4(1.0f), glm::vec3(0.8f)}, {1, glm::mat4(1.0f), glm::vec3(0.8f)}};
  return scene;
}

// The mean samples over the slab's penumbra after `steps` steps along x,
// and the mean change of its brightness from a converged render of the
// last pose against one sample's.
struct CarriedPenumbra {
  double samples, played_error, one_sample_error;
};

CarriedPenumbra penumbra_after_steps(const Light& light, int steps) {
  GpuScene scene(testing::VulkanTest::context(), block_on_slab());
  Renderer renderer(testing::VulkanTest::context());
  RenderSettings settings = playback_settings();
  settings.samples = 16;
  draw_top_view(renderer, scene, {light}, glm::vec3(0.05f), settings, settings.samples);
  const glm::mat4 still_ground(1.0f);
  for (int step = 1; step <= steps; ++step) {
    scene.set_transforms({glm::translate(glm::mat4(1.0f), glm::vec3(0.03f * float(step), 0, 0)), still_ground});
    draw_top_view(renderer, scene, {light}, glm::vec3(0.05f), settings, 1);
  }
  const RenderOutput played = renderer.read();
  Renderer converged_renderer(testing::VulkanTest::context());
  draw_top_view(converged_renderer, scene, {light}, glm::vec3(0.05f), settings, settings.samples);
  const RenderOutput converged = converged_renderer.read();
  std::vector<size_t> penumbra;
  for (size_t i = 0; i < converged.shadow.size(); ++i)
    if (std::abs(converged.depth[i] - 9.6f) < 0.01f && converged.shadow[i] > 0.1f && converged.shadow[i] < 0.9f)
      penumbra.push_back(i);
  EXPECT_GT(penumbra.size(), 20u) << "the block's penumbra lies on the slab";
  double samples = 0.0;
  for (size_t i : penumbra) samples += played.samples[i];
  return {samples / double(std::max<size_t>(penumbra.size(), 1)), mean_change(played, converged, penumbra),
          one_sample_noise(scene, {light}, glm::vec3(0.05f), settings, converged, penumbra)};
}

TEST_F(TemporalTest, AShadowThatMovedWithItsSurfaceKeepsItsHistory) {
  const CarriedPenumbra sun = penumbra_after_steps(wide_sun(), 4);
  Light lamp;
  lamp.type = LightType::Point;
  lamp.position = {-3.0f, 0.0f, 3.5f};
  lamp.radius = 0.5f;
  lamp.energy = 400.0f;
  const CarriedPenumbra point = penumbra_after_steps(lamp, 4);
  std::printf("slab's penumbra after 4 steps: sun %.1f samples (error %.4f, one sample's %.4f); "
              "point light %.1f samples\n", sun.samples, sun.played_error, sun.one_sample_error, point.samples);
  EXPECT_GT(sun.samples, 8.0) << "history carried with the moving surface";
  EXPECT_LT(sun.played_error, 0.5 * sun.one_sample_error);
  EXPECT_LT(point.samples, 4.0) << "a point light's penumbra moved over the slab: restarted";
}

// The moved caster's box is a bound on where its shadow may have moved: a
// pixel whose paths to the light cross it, but whose shadow this frame is
// history's (within kSameShadow), keeps its history, or the lit ground
// around a moving object took half of every frame's new sample and
// shimmered. The cube moves a little along x under the wide sun: the lit
// ground (lit in both poses) keeps its samples; only the shadow's ends along x move.
TEST_F(TemporalTest, AShadowThatDidNotMoveKeepsItsHistory) {
  GpuScene scene(context(), cube_over_ground());
  Renderer renderer(context());
  RenderSettings settings = playback_settings();
  settings.samples = 16;
  draw_top_view(renderer, scene, {wide_sun()}, glm::vec3(0.05f), settings, settings.samples);
  const std::vector<float> before = renderer.read().shadow;
  move_cube(scene, -0.5f + 0.02f);
  draw_top_view(renderer, scene, {wide_sun()}, glm::vec3(0.05f), settings, 1);
  const RenderOutput played = renderer.read();
  int lit = 0, restarted = 0, shadow_ends = 0;
  for (size_t i = 0; i < played.shadow.size(); ++i) {
    if (played.depth[i] < 9.5f) continue;  // (the ground only)
    const bool moved = std::abs(played.shadow[i] - before[i]) > 0.02f;
    if (before[i] > 0.999f && !moved) {
      ++lit;
      if (played.samples[i] <= 2.0f) ++restarted;
    }
    if (moved) ++shadow_ends;
  }
  std::printf("lit ground kept lit: %d pixels, %d of them restarted (history counted as one sample); pixels whose "
              "shadow moved: %d\n", lit, restarted, shadow_ends);
  ASSERT_GT(lit, 1000);
  EXPECT_LT(restarted, lit / 50);
  EXPECT_GT(shadow_ends, 0) << "where the shadow did move, the frame shows it";
}

// A still caster's shadow whose light paths pass the box of one that moved
// beside it keeps its own history: follow_shadow would read it where the
// moved caster's shadow was, a cube's width along, so the resolve takes the
// followed history only where the paths (from both ends) meet no caster
// that stayed, or where the sample says so. One cube stands still at
// y = 0, the other moves along x at y = 0.6, its box grown by the wide
// sun's cone reaching the paths from the still cube's shadow: the first
// playback frame shows that shadow's penumbra as it was (a mean change of
// 0.0023; 0.016 with the followed history taken there as well).
TEST_F(TemporalTest, AStillCastersShadowBesideAMovedOneKeepsItsHistory) {
  GpuScene scene(context(), two_cubes(0.6f, 0.0f));
  Renderer renderer(context());
  RenderSettings settings = playback_settings();
  settings.samples = 16;
  draw_top_view(renderer, scene, {wide_sun()}, glm::vec3(0.05f), settings, settings.samples);
  const RenderOutput before = renderer.read();
  scene.set_transforms(two_cubes_at(0.0f, 0.6f, 0.0f));
  draw_top_view(renderer, scene, {wide_sun()}, glm::vec3(0.05f), settings, 1);
  const RenderOutput played = renderer.read();
  // (the still cube's penumbra on the ground, off the moved one's shadow: y under 0.2)
  double change = 0.0;
  int pixels = 0;
  for (size_t i = 0; i < played.shadow.size(); ++i) {
    const double y = 2.0 - (double(i / kSize) + 0.5) / kSize * 4.0;
    if (played.depth[i] < 9.9f || y > 0.2 || y < -0.6 || before.shadow[i] > 0.95f || before.shadow[i] < 0.05f) continue;
    change += std::abs(double(played.shadow[i]) - double(before.shadow[i]));
    ++pixels;
  }
  change /= std::max(pixels, 1);
  std::printf("the still cube's penumbra: %d pixels, mean change of the Shadow pass in the first playback frame %.4f\n",
              pixels, change);
  ASSERT_GT(pixels, 100);
  EXPECT_LT(change, 0.01);
}

// Casters that move apart change little of the space between them: the
// light paths from a still caster's shadow between two moving ones cross
// the box that holds both movers, but neither mover's own box, and that
// shadow keeps its history; so does the still caster's outline, whose
// history holds it in front of the ground. Two cubes at y = +-1.2 move
// along x; the still cube's penumbra at y = 0 is 0.6 from either one's box,
// twice the wide sun's cone there. Tested against the box of both movers,
// the penumbra's noisy first sample restarted 73 of its 155 pixels' history,
// and 31 pixels of the still cube's outline were taken for a moved front.
TEST_F(TemporalTest, AStillCasterBetweenTwoMovingOnesKeepsItsHistory) {
  auto cubes_at = [](float moving_x) {
    return std::vector<glm::mat4>{glm::translate(glm::mat4(1.0f), glm::vec3(moving_x, 1.2f, 0)), glm::mat4(1.0f),
                                  glm::translate(glm::mat4(1.0f), glm::vec3(-0.5f, 0, 0)),
                                  glm::translate(glm::mat4(1.0f), glm::vec3(moving_x, -1.2f, 0))};
  };
  Scene two_movers = cube_over_ground();
  two_movers.instances.push_back({0, glm::mat4(1.0f), glm::vec3(0.8f)});
  two_movers.instances.push_back({0, glm::mat4(1.0f), glm::vec3(0.8f)});
  GpuScene scene(context(), two_movers);
  scene.set_transforms(cubes_at(-0.5f));
  Renderer renderer(context());
  RenderSettings settings = playback_settings();
  settings.samples = 16;
  draw_top_view(renderer, scene, {wide_sun()}, glm::vec3(0.05f), settings, settings.samples);
  const RenderOutput before = renderer.read();
  scene.set_transforms(cubes_at(-0.4f));
  draw_top_view(renderer, scene, {wide_sun()}, glm::vec3(0.05f), settings, 1);
  const RenderOutput played = renderer.read();
  int penumbra = 0, restarted = 0;
  for (double x = -0.2; x <= 1.2; x += 4.0 / kSize)
    for (double y = -0.4; y <= 0.4; y += 4.0 / kSize) {
      const size_t i = pixel_at(x, y);
      if (played.depth[i] < 9.9f || before.shadow[i] > 0.95f || before.shadow[i] < 0.05f) continue;
      ++penumbra;
      if (played.samples[i] <= 2.0f) ++restarted;
    }
  // (and the still cube itself, its outline too: history there held the
  // cube in front of the ground, and neither mover's box is near)
  int cube = 0, short_of_samples = 0;
  for (double x = -0.9; x <= -0.1; x += 4.0 / kSize)
    for (double y = -0.4; y <= 0.4; y += 4.0 / kSize) {
      const size_t i = pixel_at(x, y);
      ++cube;
      if (played.samples[i] < float(settings.samples)) ++short_of_samples;
    }
  std::printf("the still cube's penumbra: %d pixels, %d of them restarted; the still cube and its outline: %d "
              "pixels, %d short of their samples\n", penumbra, restarted, cube, short_of_samples);
  ASSERT_GT(penumbra, 40);
  EXPECT_EQ(restarted, 0);
  EXPECT_EQ(short_of_samples, 0);
}

// The noise of images of the floating cube against a converged one (256
// frames, without temporal reuse): root mean square of the red channel's
// difference over the pixels `pick` chooses, per pixel and of the means of
// the 4x4 tiles they fill.
struct Noise {
  int pixels = 0;
  double per_pixel = 0.0, of_tiles = 0.0;
};

Noise noise_of(const RenderOutput& image, const RenderOutput& converged, const std::function<bool(size_t)>& pick) {
  Noise noise;
  int tiles = 0;  // (those `pick` fills)
  for (int ty = 0; ty < kSize; ty += 4)
    for (int tx = 0; tx < kSize; tx += 4) {
      double difference = 0.0;
      int inside = 0;
      for (int y = ty; y < ty + 4; ++y)
        for (int x = tx; x < tx + 4; ++x) {
          const size_t i = size_t(y) * kSize + size_t(x);
          if (!pick(i)) continue;
          const double d = double(image.combined[4 * i]) - double(converged.combined[4 * i]);
          noise.per_pixel += d * d;
          difference += d;
          ++inside;
        }
      noise.pixels += inside;
      if (inside == 16) noise.of_tiles += (difference / 16.0) * (difference / 16.0), ++tiles;
    }
  noise.per_pixel = std::sqrt(noise.per_pixel / std::max(noise.pixels, 1));
  noise.of_tiles = std::sqrt(noise.of_tiles / std::max(tiles, 1));
  return noise;
}

// The floating cube at x under the world light alone: `samples` frames
// without temporal reuse.
RenderOutput sky_lit(const vk::Context& context, int samples, float x, const Camera& camera = top_view()) {
  GpuScene scene(context, cube_over_ground());
  move_cube(scene, x);
  Renderer renderer(context);
  RenderSettings settings = playback_settings();
  settings.temporal_reuse = false;
  settings.samples = samples;
  return renderer.render(scene, camera, {}, glm::vec3(0.5f), kSize, kSize, settings);
}

// One frame's samples, before any accumulation: the pixels of each 4x4 tile
// take theirs from one low-discrepancy sequence (interleaved sampling), so
// a tile's mean lies nearer the converged one than independent samples'
// would. The temporal resolve's clip and filter read such neighbourhoods.
// The ground around the cube under the world light: its cones (two a frame)
// are either blocked or not, one sample per 2x2 quad, shared. (With a random
// number per pixel and frame the tiles' error was 0.65 of a pixel's.)
TEST_F(TemporalTest, OneFramesSamplesSpreadEvenlyOverEachTile) {
  const RenderOutput single = sky_lit(context(), 1, -0.5f),
                     converged = sky_lit(context(), 256, -0.5f);
  const Noise noise = noise_of(single, converged, [&](size_t i) { return converged.depth[i] > 9.5f; });  // (the ground)
  std::printf("one frame's world light, RMS from 256 frames on %d ground pixels: %.4f per pixel, %.4f of 4x4 tile "
              "means (%.2f of it)\n", noise.pixels, noise.per_pixel, noise.of_tiles, noise.of_tiles / noise.per_pixel);
  ASSERT_GT(noise.pixels, 1000);
  ASSERT_GT(noise.per_pixel, 0.01) << "a single frame is noisy enough to tell";
  EXPECT_LT(noise.of_tiles, 0.6 * noise.per_pixel);
}

// The first playback frame after the floating cube moved, on the ground it
// uncovered (no history: this frame's sample alone) under the world light:
// the sample is filtered over the pixels around it on the same surface and
// in the same light (the light over albedo, times the pixel's albedo), so
// that it is less noisy than a single frame's. (Unfiltered, its error was
// 1.06 of a single frame's; filtered, 0.51.)
TEST_F(TemporalTest, AnUncoveredPixelsSampleIsFilteredOverItsSurface) {
  Camera camera = top_view();  // (closer: x in [-1.5, 0.5], y in [-1, 1])
  camera.world_to_view = glm::lookAt(glm::vec3(-0.5f, 0, 10), glm::vec3(-0.5f, 0, 0), glm::vec3(0, 1, 0));
  camera.projection = glm::orthoRH_NO(-1.0f, 1.0f, -1.0f, 1.0f, 0.1f, 20.0f);
  const RenderOutput single = sky_lit(context(), 1, -0.5f + kMove, camera),
                     converged = sky_lit(context(), 256, -0.5f + kMove, camera);
  GpuScene scene(context(), cube_over_ground());
  Renderer renderer(context());
  RenderSettings settings = playback_settings();
  settings.samples = 16;
  renderer.begin(scene, camera, {}, glm::vec3(0.5f), kSize, kSize, settings, true);
  for (int frame = 0; frame < settings.samples; ++frame) renderer.add_frame();
  move_cube(scene, -0.5f + kMove);
  renderer.begin(scene, camera, {}, glm::vec3(0.5f), kSize, kSize, settings, true);
  renderer.add_frame();
  const RenderOutput played = renderer.read();
  // (where the cube was, with no history within the jitter's reach either)
  auto uncovered = [&](size_t i) {
    const double wx = (double(i % kSize) + 0.5) / kSize * 2.0 - 1.5, wy = 1.0 - (double(i / kSize) + 0.5) / kSize * 2.0;
    return wx > -0.75 && wx < -0.25 && std::abs(wy) < 0.25 && played.samples[i] == 1.0f;
  };
  const Noise one_frame = noise_of(single, converged, uncovered), first_played = noise_of(played, converged, uncovered);
  std::printf("uncovered ground: %d pixels; RMS from 256 frames: one frame %.4f, first playback "
              "frame %.4f\n", one_frame.pixels, one_frame.per_pixel, first_played.per_pixel);
  ASSERT_GT(one_frame.pixels, 40);
  ASSERT_GT(one_frame.per_pixel, 0.01) << "a single frame is noisy enough to tell";
  EXPECT_LT(first_played.per_pixel, 0.8 * one_frame.per_pixel);
}

// cube_over_ground's cube moved to x by its mesh's vertices (a deforming
// caster: its placement stays, so its shadow cannot be followed).
void deform_cube_to(GpuScene& scene, float x) {
  std::vector<glm::vec3> positions = reference::box({-0.25f, -0.25f, 0.5f}, {0.25f, 0.25f, 1.0f}).positions;
  for (glm::vec3& p : positions) p.x += x - (-0.5f);
  scene.set_mesh_positions(0, positions);
}

// The moved penumbra on the ground of cube_over_ground's cube at -0.5 +
// kMove under the wide sun, against a converged render: partly lit, beside
// neither cube's top.
auto moved_penumbra_of(const RenderOutput& converged) {
  return [&converged](size_t i) {
    const double x = (double(i % kSize) + 0.5) / kSize * 4.0 - 2.0;
    return converged.shadow[i] > 0.1f && converged.shadow[i] < 0.9f && converged.depth[i] > 9.9f && x > 0.0;
  };
}

// The first playback frame after cube_over_ground's cube moved by kMove
// (`move`: by its placement or its vertices) under the wide sun, with 4
// exact rays and `short_history_rays`; and the share of it marked short of history.
std::pair<RenderOutput, double> first_frame_after_move(const vk::Context& context, RenderSettings settings,
                                                       int short_history_rays,
                                                       const std::function<void(GpuScene&)>& move) {
  settings.short_history_rays = short_history_rays;
  GpuScene scene(context, cube_over_ground());
  Renderer renderer(context);
  draw_top_view(renderer, scene, {wide_sun()}, glm::vec3(0.0f), settings, settings.samples);
  move(scene);
  draw_top_view(renderer, scene, {wide_sun()}, glm::vec3(0.0f), settings, 1);
  return {renderer.read(), renderer.stats().short_history_share};
}

// cube_over_ground with its cube at -0.5 + kMove, under the wide sun: one
// frame with `settings`, or 256 without temporal reuse.
RenderOutput moved_cube_frames(const vk::Context& context, RenderSettings settings, int samples) {
  GpuScene moved(context, cube_over_ground());
  move_cube(moved, -0.5f + kMove);
  settings.temporal_reuse = false;
  settings.samples = samples;
  Renderer renderer(context);
  return renderer.render(moved, top_view(), {wide_sun()}, glm::vec3(0.0f), kSize, kSize, settings);
}

// A moved penumbra on a still ground, where exact rays decide (a wide sun,
// 4 rays per light and sample), cast by a caster that deformed: its shadow
// cannot be followed to where it was, so the first playback frame after the
// move shows half of that frame's sample there (history stands for one
// sample where a shadow moved). The keep pass marks those pixels and they
// take short_history_rays times the rays, so that the frame is not a share
// of 4 binary rays: its noise against a converged render stays well under
// one frame's own, and under that of a frame with the usual rays there
// (short_history_rays 1). (The ratios to one frame's: 0.42 and 0.70, when
// the caster moved by its placement before shadows were followed.)
TEST_F(TemporalTest, ADeformedCastersMovedPenumbraTakesMoreRaysInItsFirstFrame) {
  RenderSettings settings = playback_settings();
  settings.exact_rays = 4;
  settings.samples = 16;
  auto deform = [](GpuScene& scene) { deform_cube_to(scene, -0.5f + kMove); };
  const auto [played, marked] = first_frame_after_move(context(), settings, 4, deform);
  const RenderOutput usual_rays = first_frame_after_move(context(), settings, 1, deform).first;
  const RenderOutput converged = moved_cube_frames(context(), settings, 256),
                     one_frame = moved_cube_frames(context(), settings, 1);
  // (short of history: the moved shadow's history restarted)
  const auto penumbra = moved_penumbra_of(converged);
  auto moved_penumbra = [&](size_t i) { return penumbra(i) && played.samples[i] <= 2.0f; };
  const Noise more = noise_of(played, converged, moved_penumbra), usual = noise_of(usual_rays, converged, moved_penumbra),
              own = noise_of(one_frame, converged, moved_penumbra);
  std::printf("moved penumbra: %d pixels; RMS from 256 frames: one frame of its own %.4f, first playback frame %.4f "
              "(%.2f of it), with the usual rays %.4f (%.2f); marked short of history: %.3f of the image\n",
              own.pixels, own.per_pixel, more.per_pixel, more.per_pixel / own.per_pixel, usual.per_pixel,
              usual.per_pixel / own.per_pixel, marked);
  ASSERT_GT(own.pixels, 40);
  ASSERT_GT(own.per_pixel, 0.02) << "a frame of its own is noisy enough to tell";
  EXPECT_LT(more.per_pixel, 0.5 * own.per_pixel);
  EXPECT_LT(more.per_pixel, 0.8 * usual.per_pixel);
  // (the marked pixels: at least the moved penumbra, and not the whole image)
  EXPECT_GE(marked, double(own.pixels) / double(kSize * kSize));
  EXPECT_LT(marked, 0.5);
}

// A caster moved by its placement carries its shadow along: the first
// playback frame's moved penumbra takes the history of the shadow where it
// was (follow_shadow in shaders/temporal_history.glsl.h) with its samples,
// with no more rays than any frame (short_history_rays 1). Its noise
// against a converged render is as low as 16 frames' (0.18 of a frame's
// own), where the same move by the caster's vertices (a deformation, not
// followed: history of one sample there) shows 0.69 of it.
TEST_F(TemporalTest, AMovedCastersShadowIsFollowedToItsHistory) {
  RenderSettings settings = playback_settings();
  settings.exact_rays = 4;
  settings.samples = 16;
  const RenderOutput followed =
      first_frame_after_move(context(), settings, 1, [](GpuScene& scene) { move_cube(scene, -0.5f + kMove); }).first;
  const RenderOutput deformed =
      first_frame_after_move(context(), settings, 1, [](GpuScene& scene) { deform_cube_to(scene, -0.5f + kMove); }).first;
  const RenderOutput converged = moved_cube_frames(context(), settings, 256),
                     one_frame = moved_cube_frames(context(), settings, 1);
  const auto penumbra = moved_penumbra_of(converged);
  // (where the shadow moved: the penumbra now, lit or in the umbra before)
  auto moved = [&](size_t i) {
    const double x = (double(i % kSize) + 0.5) / kSize * 4.0 - 2.0;
    return penumbra(i) && x > 0.6;
  };
  const Noise shown = noise_of(followed, converged, moved), unfollowed = noise_of(deformed, converged, moved),
              own = noise_of(one_frame, converged, moved);
  double samples = 0.0;
  for (size_t i = 0; i < followed.samples.size(); ++i)
    if (moved(i)) samples += followed.samples[i] / double(std::max(shown.pixels, 1));
  std::printf("moved penumbra: %d pixels, %.1f samples on average; RMS from 256 frames: one frame of its own %.4f, "
              "first playback frame %.4f (%.2f of it), its caster deformed %.4f (%.2f)\n",
              shown.pixels, samples, own.per_pixel, shown.per_pixel, shown.per_pixel / own.per_pixel,
              unfollowed.per_pixel, unfollowed.per_pixel / own.per_pixel);
  ASSERT_GT(own.pixels, 40);
  ASSERT_GT(own.per_pixel, 0.02) << "a frame of its own is noisy enough to tell";
  EXPECT_GT(samples, 8.0) << "the followed history's samples carried over";
  EXPECT_LT(shown.per_pixel, 0.3 * own.per_pixel);
  EXPECT_LT(shown.per_pixel, 0.4 * unfollowed.per_pixel);
}

// A step of two_cubes: the first cube at (x, 1), the second at (-0.5, y),
// then `frames` frames.
struct CubesStep {
  float x, y;
  int frames;
};

// Plays `steps` in two renderers, one drawing each playback step's changed
// region alone (RenderSettings::changed_region_only) and one the whole
// image: every pixel's colour and shadow must come out the same. Returns
// the smallest share of the image a step of one frame drew.
double expect_region_draws_as_whole(const Camera& camera, const std::vector<Light>& lights, glm::vec3 sky,
                                    glm::ivec2 size, const std::vector<CubesStep>& steps) {
  const vk::Context& context = testing::VulkanTest::context();
  GpuScene whole_scene(context, two_cubes(1.0f, -1.0f)), region_scene(context, two_cubes(1.0f, -1.0f));
  Renderer whole(context), region(context);
  RenderSettings settings = playback_settings();
  settings.samples = 4;
  settings.quick_first_frame = true;
  RenderSettings whole_settings = settings;
  whole_settings.changed_region_only = false;
  double smallest_share = 1.0;
  int step_index = 0;
  for (const auto& [x, y, frames] : steps) {
    for (auto [scene, renderer, drawn] :
         {std::tuple{&whole_scene, &whole, &whole_settings}, std::tuple{&region_scene, &region, &settings}}) {
      scene->set_transforms(two_cubes_at(x, 1.0f, y));
      renderer->begin(*scene, camera, lights, sky, size.x, size.y, *drawn, true);
      for (int frame = 0; frame < frames; ++frame) {
        renderer->add_frame();
        // (the step itself; the frames after it shade the tiles its keep pass did not keep, in both)
        if (frame == 0 && renderer == &whole) EXPECT_DOUBLE_EQ(whole.stats().drawn_share, 1.0);
      }
    }
    if (frames == 1) smallest_share = std::min(smallest_share, region.stats().drawn_share);
    const RenderOutput a = whole.read(), b = region.read();
    int differing = 0;
    float worst = 0.0f;
    for (size_t i = 0; i < a.shadow.size(); ++i) {
      float difference = std::abs(a.shadow[i] - b.shadow[i]);
      for (int c = 0; c < 3; ++c) difference = std::max(difference, std::abs(a.combined[4 * i + c] - b.combined[4 * i + c]));
      worst = std::max(worst, difference);
      if (difference > 1e-5f) differing++;
    }
    std::printf("step %d (cubes at x %.1f, y %.1f, %d frames): drawn share %.2f, pixels differing %d (largest %.2e)\n",
                step_index++, x, y, frames, region.stats().drawn_share, differing, worst);
    EXPECT_EQ(differing, 0) << "a pixel outside the drawn region would have changed";
  }
  return smallest_share;
}

// A playback step draws the region its change can reach on screen and the
// pixels left unsettled before it: two cubes on a ground under a sun, a
// point light and a spot with the sky's light, seen in perspective at a
// size of partial tiles; one cube moves for some steps, the scene then
// settles (and once draws a jittered frame with nothing moved, over the
// whole image), and it moves again.
TEST_F(TemporalTest, APlaybackStepDrawsItsChangedRegionAloneAndEveryPixelComesOutTheSame) {
  Camera camera;
  camera.world_to_view = glm::lookAt(glm::vec3(1.0f, -4.0f, 3.0f), glm::vec3(-0.3f, 0.0f, 0.3f), glm::vec3(0, 0, 1));
  camera.projection = glm::perspectiveRH_NO(0.9f, 190.0f / 142.0f, 0.1f, 40.0f);
  Light point;
  point.type = LightType::Point;
  point.position = {-2.0f, 1.0f, 2.5f};
  point.energy = 60.0f;
  point.radius = 0.3f;
  Light spot = point;
  spot.type = LightType::Spot;
  spot.position = {1.5f, -1.0f, 3.0f};
  spot.direction = glm::normalize(glm::vec3(-0.4f, 0.3f, -1.0f));
  spot.spot_size = 1.2f;
  spot.spot_blend = 0.3f;
  const double smallest_share = expect_region_draws_as_whole(
      camera, {wide_sun(), point, spot}, glm::vec3(0.1f), {190, 142},
      {{-0.5f, -1.0f, 4}, {-0.4f, -1.0f, 1}, {-0.3f, -1.0f, 1}, {-0.2f, -1.0f, 1}, {-0.2f, -1.0f, 4}, {0.1f, -1.0f, 1},
       {0.3f, -1.0f, 2}, {0.3f, -1.0f, 1}, {0.5f, -1.0f, 1}, {0.5f, -1.0f, 4}, {0.7f, -1.0f, 1}, {0.8f, -1.0f, 1}});
  EXPECT_LT(smallest_share, 0.75) << "some playback step drew less than the whole image";
}

// The pixels a step left unsettled are drawn in the next though its change
// lies elsewhere: from the top, under the tilted sun, the first cube moves
// for two steps, then the second (2 units away) for two more.
TEST_F(TemporalTest, APlaybackStepDrawsThePixelsTheStepBeforeLeftUnsettled) {
  const double smallest_share = expect_region_draws_as_whole(
      top_view(), {tilted_sun()}, glm::vec3(0.1f), {128, 128},
      {{-0.5f, -1.0f, 4}, {-0.4f, -1.0f, 1}, {-0.3f, -1.0f, 1}, {-0.3f, -1.1f, 1}, {-0.3f, -1.2f, 1}});
  EXPECT_LT(smallest_share, 0.6) << "the steps drew less than the whole image";
}

}  // namespace
}  // namespace rtsdf
