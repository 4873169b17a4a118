// Adaptive sampling (RenderSettings::noise_threshold): once half the samples
// are in, the tiles whose pixels' samples agree take no more, and an image
// whose every tile agrees ends early. The pixels whose samples differ (a
// penumbra) take every sample, as without it.
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "reference/shapes.h"
#include "renderer.h"
#include "viewport.h"
#include "top_view.h"
#include "vulkan_test.h"

namespace rtsdf {
namespace {

using testing::tilted_sun;
using testing::top_view;

constexpr int kSize = 64;  // pixels over the 4 x 4 top view: 8 x 8 tiles

class AdaptiveSamplingTest : public testing::VulkanTest {};

Scene ground(bool with_cube) {
  Scene scene;
  scene.meshes = {reference::sheet({-20, -20}, {20, 20}, 0.0f)};
  scene.instances = {{0, glm::mat4(1.0f), glm::vec3(0.8f)}};
  if (with_cube) {
    scene.meshes.push_back(reference::box({-0.25f, -0.25f, 0.5f}, {0.25f, 0.25f, 1.0f}));
    scene.instances.push_back({1, glm::mat4(1.0f), glm::vec3(0.8f)});
  }
  return scene;
}

RenderSettings small_fields(float noise_threshold) {
  RenderSettings settings;
  settings.coarse_resolution = 32;
  settings.fine_resolution = 64;
  settings.noise_threshold = noise_threshold;
  return settings;
}

View top_view_under_the_sun() {
  View view;
  view.camera = top_view();
  view.lights = {tilted_sun()};
  view.ambient = glm::vec3(0.1f);
  view.width = view.height = kSize;
  return view;
}

RenderOutput render_top_view(const vk::Context& context, const Scene& scene, const RenderSettings& settings) {
  GpuScene gpu(context, scene);
  Renderer renderer(context);
  const View view = top_view_under_the_sun();
  return renderer.render(gpu, view.camera, view.lights, view.ambient, view.width, view.height, settings);
}

TEST_F(AdaptiveSamplingTest, TilesWhosePixelsAgreeStopAndThePenumbraTakesEverySample) {
  const Scene scene = ground(/*with_cube=*/true);
  const RenderOutput full = render_top_view(context(), scene, small_fields(0.0f));
  const RenderOutput adaptive = render_top_view(context(), scene, small_fields(0.03f));
  EXPECT_EQ(full.samples_done, 16);
  EXPECT_DOUBLE_EQ(full.stats.sampled_share, 1.0);
  // The first half of the frames shade every pixel; the lit and shadowed
  // ground's tiles stop there, the penumbra's go on.
  EXPECT_GT(adaptive.stats.sampled_share, 0.5);
  EXPECT_LT(adaptive.stats.sampled_share, 0.85);
  EXPECT_EQ(adaptive.samples_done, 16) << "the penumbra's tiles took every frame";
  int penumbra = 0, same = 0;
  double sum = 0.0, largest = 0.0;
  for (size_t i = 0; i < full.shadow.size(); ++i) {
    const double difference = std::abs(double(adaptive.shadow[i]) - full.shadow[i]);
    sum += difference;
    largest = std::max(largest, difference);
    if (full.shadow[i] > 0.05f && full.shadow[i] < 0.95f) {
      ++penumbra;
      same += difference < 1e-5 ? 1 : 0;
    }
  }
  ASSERT_GT(penumbra, 20);
  EXPECT_GE(same, penumbra * 95 / 100) << "of the penumbra's pixels, those that took the same samples";
  EXPECT_LT(sum / double(full.shadow.size()), 2e-3);
  EXPECT_LT(largest, 0.1);
  EXPECT_EQ(context().validation_message_count(), 0);
}

TEST_F(AdaptiveSamplingTest, AnImageWhosePixelsAllAgreeEndsAtHalfItsSamples) {
  const Scene scene = ground(/*with_cube=*/false);
  const RenderOutput full = render_top_view(context(), scene, small_fields(0.0f));
  const RenderOutput adaptive = render_top_view(context(), scene, small_fields(0.03f));
  EXPECT_EQ(full.samples_done, 16);
  EXPECT_EQ(adaptive.samples_done, 8);
  EXPECT_DOUBLE_EQ(adaptive.stats.sampled_share, 0.5);
  for (size_t i = 0; i < full.combined.size(); ++i) ASSERT_NEAR(adaptive.combined[i], full.combined[i], 1e-4f) << i;
  // Its pixels count as sampled in full: a later change's keep pass takes them as settled.
  for (float samples : adaptive.samples) ASSERT_EQ(samples, 16.0f);
}

// csm_jitter's maps move over the light every frame: a pixel its first
// maps all saw lit may lie in the penumbra of the light's points to come.
TEST_F(AdaptiveSamplingTest, JitteredShadowMapsTakeEverySample) {
  RenderSettings settings = small_fields(0.03f);
  settings.shadow_method = ShadowMethod::CsmJitter;
  settings.shadow_map_size = 256;
  const RenderOutput out = render_top_view(context(), ground(/*with_cube=*/true), settings);
  EXPECT_EQ(out.samples_done, 16);
  EXPECT_DOUBLE_EQ(out.stats.sampled_share, 1.0);
}

TEST_F(AdaptiveSamplingTest, AViewportWhosePixelsAllAgreeConvergesAtHalfItsSamples) {
  Viewport viewport(context(), nullptr);
  viewport.sync(ground(/*with_cube=*/false));
  const View view = top_view_under_the_sun();
  RenderSettings settings = small_fields(0.03f);
  int draws = 0;
  ViewportFrame frame;
  for (; draws < 20 && !frame.converged; ++draws) frame = viewport.draw(view, settings);
  EXPECT_EQ(draws, 8);
  EXPECT_EQ(frame.image.samples_done, 8);
  EXPECT_FALSE(viewport.draw(view, settings).advanced) << "a converged viewport does no work";
}

// A move that shows nowhere on screen (a cube off the view, its shadow
// falling further off): its playback step keeps every pixel, and the
// viewport has converged after that one frame.
TEST_F(AdaptiveSamplingTest, AMoveThatShowsNowhereConvergesInOneStep) {
  Viewport viewport(context(), nullptr);
  viewport.sync(ground(/*with_cube=*/true));
  auto cube_at = [&](float x) {
    viewport.set_transforms({glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), glm::vec3(x, 0, 0))});
  };
  cube_at(12.0f);
  const View view = top_view_under_the_sun();
  RenderSettings settings = small_fields(0.03f);
  settings.temporal_reuse = true;
  ViewportFrame frame;
  for (int draw = 0; draw < 40 && !frame.converged; ++draw) frame = viewport.draw(view, settings);
  ASSERT_TRUE(frame.converged);
  cube_at(13.0f);
  frame = viewport.draw(view, settings);
  EXPECT_TRUE(frame.advanced);
  EXPECT_TRUE(frame.converged) << "every pixel kept from history";
  EXPECT_FALSE(viewport.draw(view, settings).advanced);
  EXPECT_EQ(context().validation_message_count(), 0);
}

TEST_F(AdaptiveSamplingTest, ANoiseThresholdOutOfRangeIsAnError) {
  GpuScene gpu(context(), ground(false));
  Renderer renderer(context());
  for (float bad : {-0.01f, 1.5f, std::nanf("")})
    EXPECT_THROW(renderer.render(gpu, top_view(), {tilted_sun()}, glm::vec3(0.1f), 8, 8, small_fields(bad)), Error)
        << bad;
}

}  // namespace
}  // namespace rtsdf
