// Where on screen a change can show (screen_region.h): the rectangles a
// playback step draws alone. Each must hold what the keep pass's tests would
// find (a moved box, the contact around it, each light's shadow volume) and
// stay well short of the whole image where the change is small.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "lights.h"
#include "screen_region.h"

namespace rtsdf {
namespace {

constexpr glm::ivec2 kSize(200, 100);

// OpenGL clip space to Vulkan's, as the renderer's world_to_clip has it.
const glm::mat4 kGlToVulkan(1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 0.5f, 0, 0, 0, 0.5f, 1);

// Straight down on the ground z = 0, x in [-4, 4] and y in [-2, 2] across the image.
glm::mat4 top_view() {
  return kGlToVulkan * glm::orthoRH_NO(-4.0f, 4.0f, -2.0f, 2.0f, 0.1f, 40.0f) *
         glm::lookAt(glm::vec3(0, 0, 20), glm::vec3(0), glm::vec3(0, 1, 0));
}

// The pixel where the top view sees ground point (x, y).
glm::ivec2 seen_at(float x, float y) {
  return glm::ivec2(int((x + 4.0f) / 8.0f * kSize.x), int((2.0f - y) / 4.0f * kSize.y));
}

bool holds(const PixelRect& rect, glm::ivec2 pixel) {
  return glm::all(glm::greaterThanEqual(pixel, rect.lo)) && glm::all(glm::lessThan(pixel, rect.hi));
}

double share(const PixelRect& rect) { return double(rect.size().x) * rect.size().y / (double(kSize.x) * kSize.y); }

// A unit box standing 2 above the ground at the origin, which moved there.
gpu::FrameData box_moved() {
  gpu::FrameData frame{};
  frame.steady_world_to_clip = top_view();
  frame.changed_lo = frame.moved_lo = glm::vec4(-0.5f, -0.5f, 2.0f, 1.0f);
  frame.changed_hi = frame.moved_hi = glm::vec4(0.5f, 0.5f, 3.0f, 1.0f);
  return frame;
}

const Bounds kGround{{-10.0f, -10.0f, 0.0f}, {10.0f, 10.0f, 3.0f}};  // (everything seen)

TEST(PixelRect, UnitesGrowsWithinTheImageAndTellsEmpty) {
  const PixelRect a{{10, 10}, {20, 30}}, b{{15, 5}, {40, 12}}, none;
  EXPECT_TRUE(none.is_empty());
  EXPECT_EQ(a.united(b), (PixelRect{{10, 5}, {40, 30}}));
  EXPECT_EQ(a.united(none), a);
  EXPECT_EQ(none.united(b), b);
  EXPECT_EQ(a.grown(15, kSize), (PixelRect{{0, 0}, {35, 45}}));
  EXPECT_EQ(PixelRect({{190, 90}, {200, 100}}).grown(5, kSize), (PixelRect{{185, 85}, {200, 100}}));
  EXPECT_TRUE(none.grown(5, kSize).is_empty());
  EXPECT_EQ(a.intersected(b), (PixelRect{{15, 10}, {20, 12}}));
  EXPECT_TRUE(a.intersected(PixelRect{{25, 0}, {30, 5}}).is_empty());
}

TEST(ScreenRegion, AHullBehindTheCameraTakesTheWholeImageAndOneOffScreenNone) {
  const glm::mat4 perspective = kGlToVulkan * glm::perspectiveRH_NO(1.0f, 2.0f, 0.1f, 40.0f) *
                                glm::lookAt(glm::vec3(0, -5, 1), glm::vec3(0, 0, 1), glm::vec3(0, 0, 1));
  EXPECT_EQ(project_hull(perspective, kSize, {{0, 0, 1}, {0, -10, 1}}), PixelRect::whole(kSize));
  const PixelRect ahead = project_hull(perspective, kSize, {{-0.1f, 0, 0.9f}, {0.1f, 0, 1.1f}});
  EXPECT_TRUE(holds(ahead, kSize / 2));
  EXPECT_LT(share(ahead), 0.05);
  EXPECT_TRUE(project_hull(perspective, kSize, {{50, 0, 1}, {60, 0, 1}}).is_empty()) << "far off to the right";
}

// A sun shining down at 45 degrees towards +x: the box's shadow falls on the
// ground 2 to 3 units towards +x. The region holds the box, the contact
// around it and that shadow, and not the ground beyond.
TEST(ScreenRegion, ASunsRegionHoldsTheMovedBoxAndItsShadowOnTheGround) {
  Light sun;
  sun.direction = glm::normalize(glm::vec3(1, 0, -1));
  sun.sun_angle = 0.02f;
  const PixelRect region = change_on_screen(box_moved(), {to_gpu(sun)}, kGround, kSize, 1.0f);
  for (float y : {-0.5f, 0.5f}) {
    EXPECT_TRUE(holds(region, seen_at(-0.5f, y))) << "the box";
    EXPECT_TRUE(holds(region, seen_at(2.0f + 0.5f, y))) << "its shadow's near edge";
    EXPECT_TRUE(holds(region, seen_at(3.0f + 0.5f, y))) << "its far edge";
  }
  EXPECT_FALSE(holds(region, seen_at(-2.5f, 0.0f))) << "the ground the light comes from";
  EXPECT_FALSE(holds(region, seen_at(0.0f, 1.8f))) << "the ground beside";
  EXPECT_LT(share(region), 0.5);
}

// Surfaces are seen only within `visible`: where the ground ends at x = 1,
// the sun's shadow volume (which would reach x = 3.5) and the contact
// around the box end there too; the moved box itself does not (its old
// outline may show anywhere it was).
TEST(ScreenRegion, TheTestsOfSurfacePointsEndWhereNothingIsSeen) {
  Light sun;
  sun.direction = glm::normalize(glm::vec3(1, 0, -1));
  sun.sun_angle = 0.02f;
  const Bounds narrow{{-10.0f, -10.0f, 0.0f}, {1.0f, 10.0f, 3.0f}};
  const PixelRect region = change_on_screen(box_moved(), {to_gpu(sun)}, narrow, kSize, 1.0f);
  EXPECT_TRUE(holds(region, seen_at(0.9f, 0.0f)));
  EXPECT_FALSE(holds(region, seen_at(1.5f, 0.0f)));
  gpu::FrameData moved_beyond = box_moved();
  moved_beyond.changed_lo.w = 0.0f;  // (a box that casts no shadow, moved from x = 1.5 to 2.5)
  moved_beyond.moved_lo = glm::vec4(1.5f, -0.5f, 2.0f, 1.0f);
  moved_beyond.moved_hi = glm::vec4(2.5f, 0.5f, 3.0f, 1.0f);
  EXPECT_TRUE(holds(change_on_screen(moved_beyond, {to_gpu(sun)}, narrow, kSize, 1.0f), seen_at(2.0f, 0.0f)));
}

// A point light above: the shadow is the box's outline scaled from the light
// down to the ground. The region holds it, and a light inside the box takes
// the whole image (every path leaves through it).
TEST(ScreenRegion, APointLightsRegionHoldsTheShadowsProjectionAndALightInsideTakesAll) {
  Light point;
  point.type = LightType::Point;
  point.position = {-1.0f, 0.0f, 6.0f};
  point.radius = 0.1f;
  const PixelRect region = change_on_screen(box_moved(), {to_gpu(point)}, kGround, kSize, 1.0f);
  // (a corner at height 2 seen from the light at height 6 lands 6/4 as far out on the ground)
  for (glm::vec2 corner : {glm::vec2(0.5f, 0.5f), glm::vec2(0.5f, -0.5f), glm::vec2(-0.5f, 0.5f)}) {
    const glm::vec2 on_ground = glm::vec2(-1.0f, 0.0f) + 1.5f * (corner - glm::vec2(-1.0f, 0.0f));
    EXPECT_TRUE(holds(region, seen_at(on_ground.x, on_ground.y))) << on_ground.x << ", " << on_ground.y;
  }
  EXPECT_FALSE(holds(region, seen_at(-3.5f, 0.0f)));
  EXPECT_LT(share(region), 0.5);
  point.position = {0.0f, 0.0f, 2.5f};
  EXPECT_EQ(change_on_screen(box_moved(), {to_gpu(point)}, kGround, kSize, 1.0f), PixelRect::whole(kSize));
}

TEST(ScreenRegion, NothingChangedIsEmpty) {
  gpu::FrameData frame{};
  frame.steady_world_to_clip = top_view();
  Light sun;
  EXPECT_TRUE(change_on_screen(frame, {to_gpu(sun)}, kGround, kSize, 1.0f).is_empty());
}

}  // namespace
}  // namespace rtsdf
