// Where on screen a change can show (screen_region.h): the rectangles a
// playback step draws alone. Each must hold what the keep pass's tests would
// find (a moved box, the contact around it, each light's shadow volume) and
// stay well short of the whole image where the change is small.
#include <gtest/gtest.h>

#include <cstdio>

#include <glm/gtc/matrix_transform.hpp>

#include "gpu_scene.h"
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
bool holds(const TileMask& tiles, glm::ivec2 pixel) { return tiles.holds(pixel); }

double share(const PixelRect& rect) { return double(rect.size().x) * rect.size().y / (double(kSize.x) * kSize.y); }
double share(const TileMask& tiles) { return tiles.share(); }

// A unit box standing 2 above the ground at the origin, which moved there.
gpu::FrameData box_moved() {
  gpu::FrameData frame{};
  frame.steady_world_to_clip = top_view();
  frame.changed_lo = frame.moved_lo = glm::vec4(-0.5f, -0.5f, 2.0f, 1.0f);
  frame.changed_hi = frame.moved_hi = glm::vec4(0.5f, 0.5f, 3.0f, 1.0f);
  return frame;
}

const std::vector<Bounds> kGround{{{-10.0f, -10.0f, 0.0f}, {10.0f, 10.0f, 3.0f}}};  // (everything seen)

TEST(PixelRect, GrowsWithinTheImageIntersectsAndTellsEmpty) {
  const PixelRect a{{10, 10}, {20, 30}}, b{{15, 5}, {40, 12}}, none;
  EXPECT_TRUE(none.is_empty());
  EXPECT_EQ(a.grown(15, kSize), (PixelRect{{0, 0}, {35, 45}}));
  EXPECT_EQ(PixelRect({{190, 90}, {200, 100}}).grown(5, kSize), (PixelRect{{185, 85}, {200, 100}}));
  EXPECT_TRUE(none.grown(5, kSize).is_empty());
  EXPECT_EQ(a.intersected(b), (PixelRect{{15, 10}, {20, 12}}));
  EXPECT_TRUE(a.intersected(PixelRect{{25, 0}, {30, 5}}).is_empty());
}

TEST(TileMask, MarksTheTilesOfARectangleAndItsOutsideCoversTheRestOnce) {
  TileMask tiles(kSize);  // (25 x 13 tiles, the last row half outside the image)
  EXPECT_TRUE(tiles.is_empty());
  tiles.add(PixelRect{{10, 20}, {17, 21}});  // (tiles x 1-2, y 2)
  tiles.add(PixelRect{{190, 97}, {300, 300}});  // (cut by the image: tile 23-24, 12)
  EXPECT_EQ(tiles.indices(), (std::vector<uint32_t>{1 + 25 * 2, 2 + 25 * 2, 23 + 25 * 12, 24 + 25 * 12}));
  EXPECT_EQ(tiles.bounds(), (PixelRect{{8, 16}, {200, 100}}));
  EXPECT_DOUBLE_EQ(tiles.share(), 4.0 / (25 * 13));
  EXPECT_TRUE(tiles.holds({16, 23}));
  EXPECT_FALSE(tiles.holds({24, 23}));
  std::vector<int> covered(size_t(kSize.x) * kSize.y, 0);
  for (const PixelRect& rect : tiles.outside())
    for (int y = rect.lo.y; y < rect.hi.y; ++y)
      for (int x = rect.lo.x; x < rect.hi.x; ++x) covered[size_t(x) + size_t(kSize.x) * y]++;
  for (int y = 0; y < kSize.y; ++y)
    for (int x = 0; x < kSize.x; ++x)
      ASSERT_EQ(covered[size_t(x) + size_t(kSize.x) * y], tiles.holds({x, y}) ? 0 : 1) << x << ", " << y;
  EXPECT_EQ(TileMask::whole(kSize).share(), 1.0);
  EXPECT_TRUE(TileMask::whole(kSize).outside().empty());
}

TEST(TileMask, AConvexPolygonMarksTheTilesItReachesAndNoneBesideIt) {
  TileMask tiles(kSize);
  // A thin diagonal band from (20, 10) to (180, 90), half a pixel wide.
  tiles.add_convex({{20.0f, 10.0f}, {180.0f, 90.0f}, {180.5f, 89.5f}, {20.5f, 9.5f}}, 0.0f, PixelRect::whole(kSize));
  for (float t : {0.0f, 0.3f, 0.7f, 1.0f}) {
    const glm::vec2 on = glm::mix(glm::vec2(20.0f, 10.0f), glm::vec2(180.0f, 90.0f), t);
    EXPECT_TRUE(tiles.holds(glm::ivec2(on))) << on.x << ", " << on.y;
  }
  EXPECT_FALSE(tiles.holds({170, 20})) << "the far corner of its bounds";
  EXPECT_FALSE(tiles.holds({30, 80}));
  EXPECT_LT(tiles.share(), 0.25 * double(tiles.bounds().size().x * tiles.bounds().size().y) / (kSize.x * kSize.y));
  // Grown by a margin, within a rectangle.
  TileMask grown(kSize);
  grown.add_convex({{20.0f, 10.0f}, {180.0f, 90.0f}, {180.5f, 89.5f}, {20.5f, 9.5f}}, 12.0f, PixelRect{{0, 0}, {100, 100}});
  EXPECT_TRUE(grown.holds({60, 40}));
  EXPECT_TRUE(grown.holds({60, 50})) << "10 pixels off the band";
  EXPECT_FALSE(grown.holds({140, 70})) << "beyond the rectangle and its margin";
}

// A sun shining across the image at a slant: the box's shadow falls 2 to 3
// units towards +x and 0.8 to 1.2 towards +y. The tiles hold the box and
// its shadow, and leave the corners of the rectangle holding both.
TEST(ScreenRegion, ASlantedShadowTakesItsOwnTilesNotTheirBoundingRectangle) {
  Light sun;
  sun.direction = glm::normalize(glm::vec3(1.0f, 0.4f, -1.0f));
  sun.sun_angle = 0.02f;
  const TileMask region = change_on_screen(box_moved(), {to_gpu(sun)}, kGround, kSize, 1.0f);
  for (glm::vec2 corner : {glm::vec2(-0.5f, -0.5f), glm::vec2(0.5f, 0.5f), glm::vec2(-0.5f, 0.5f), glm::vec2(0.5f, -0.5f)}) {
    EXPECT_TRUE(region.holds(seen_at(corner.x, corner.y))) << "the box";
    for (float height : {2.0f, 3.0f})
      EXPECT_TRUE(region.holds(seen_at(corner.x + height, corner.y + 0.4f * height))) << "its shadow";
  }
  const PixelRect bounds = region.bounds();
  for (glm::vec2 corner : {glm::vec2(-1.3f, 1.85f), glm::vec2(3.8f, -1.3f)})
    EXPECT_TRUE(holds(bounds, seen_at(corner.x, corner.y)) && !region.holds(seen_at(corner.x, corner.y)))
        << "a corner of the rectangle left out: " << corner.x << ", " << corner.y;
  EXPECT_LT(region.share(), 0.85 * share(bounds));
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
  const TileMask region = change_on_screen(box_moved(), {to_gpu(sun)}, kGround, kSize, 1.0f);
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
  const std::vector<Bounds> narrow{{{-10.0f, -10.0f, 0.0f}, {1.0f, 10.0f, 3.0f}}};
  const TileMask region = change_on_screen(box_moved(), {to_gpu(sun)}, narrow, kSize, 1.0f);
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
  const TileMask region = change_on_screen(box_moved(), {to_gpu(point)}, kGround, kSize, 1.0f);
  // (a corner at height 2 seen from the light at height 6 lands 6/4 as far out on the ground)
  for (glm::vec2 corner : {glm::vec2(0.5f, 0.5f), glm::vec2(0.5f, -0.5f), glm::vec2(-0.5f, 0.5f)}) {
    const glm::vec2 on_ground = glm::vec2(-1.0f, 0.0f) + 1.5f * (corner - glm::vec2(-1.0f, 0.0f));
    EXPECT_TRUE(holds(region, seen_at(on_ground.x, on_ground.y))) << on_ground.x << ", " << on_ground.y;
  }
  EXPECT_FALSE(holds(region, seen_at(-3.5f, 0.0f)));
  EXPECT_LT(share(region), 0.5);
  point.position = {0.0f, 0.0f, 2.5f};
  EXPECT_EQ(change_on_screen(box_moved(), {to_gpu(point)}, kGround, kSize, 1.0f).share(), 1.0);
}

// A box standing on a ground, seen from above at a slant: its contact
// volume (the box grown by a share of its diagonal) covers, on screen, much
// of the ground behind it, but the surfaces it holds are the box and the
// ground at its foot. Taken apart, the boxes of what is seen (the ground's
// slab, the box) give a region that holds the foot and lies within the
// region of one box holding both, smaller.
TEST(ScreenRegion, EachSeenBoxTakesItsOwnPartOfAContactVolume) {
  gpu::FrameData frame{};
  frame.steady_world_to_clip = kGlToVulkan * glm::perspectiveRH_NO(0.8f, 2.0f, 0.1f, 40.0f) *
                               glm::lookAt(glm::vec3(0, -8, 6), glm::vec3(0, 0, 0.5f), glm::vec3(0, 0, 1));
  frame.changed_lo = frame.moved_lo = glm::vec4(-0.5f, -0.5f, 0.0f, 1.0f);
  frame.changed_hi = frame.moved_hi = glm::vec4(0.5f, 0.5f, 2.0f, 1.0f);
  const Bounds ground{{-10.0f, -10.0f, -0.1f}, {10.0f, 10.0f, 0.0f}}, box{glm::vec3(frame.changed_lo), glm::vec3(frame.changed_hi)};
  const TileMask apart = change_on_screen(frame, {}, {ground, box}, kSize, 1.0f);
  const TileMask together = change_on_screen(frame, {}, {{ground.lo, glm::max(ground.hi, box.hi)}}, kSize, 1.0f);
  auto seen = [&](glm::vec3 p) {
    const glm::vec4 clip = frame.steady_world_to_clip * glm::vec4(p, 1.0f);
    return glm::ivec2((glm::vec2(clip) / clip.w + 1.0f) * 0.5f * glm::vec2(kSize));
  };
  for (glm::vec3 foot : {glm::vec3(0.9f, 0.0f, 0.0f), glm::vec3(-0.9f, 0.3f, 0.0f), glm::vec3(0.0f, -1.0f, 0.0f), glm::vec3(0.2f, 1.0f, 0.0f)}) {
    EXPECT_TRUE(apart.holds(seen(foot))) << foot.x << ", " << foot.y;
    EXPECT_TRUE(together.holds(seen(foot)));
  }
  std::printf("share of the image: boxes apart %.3f, one box %.3f\n", apart.share(), together.share());
  EXPECT_LT(apart.share(), 0.9 * together.share());
  for (uint32_t tile : apart.indices())
    EXPECT_TRUE(together.holds_tile({int(tile % uint32_t(apart.tiles().x)), int(tile / uint32_t(apart.tiles().x))}));
}

// Two casters that moved, at y = -1.5 and 1.5, each with its own box
// (FrameData::changed_casters and moved_instances): the region holds each
// one and its shadow, but not the ground between them, which the box
// holding both would take in.
TEST(ScreenRegion, CastersThatMovedApartTakeTheirOwnShadowsNotTheGroundBetween) {
  Light sun;
  sun.direction = glm::normalize(glm::vec3(1, 0, -1));
  sun.sun_angle = 0.02f;
  gpu::FrameData frame = box_moved();
  frame.changed_lo = frame.moved_lo = glm::vec4(-0.5f, -1.9f, 2.0f, 1.0f);
  frame.changed_hi = frame.moved_hi = glm::vec4(0.5f, 1.9f, 3.0f, 1.0f);
  const TileMask together = change_on_screen(frame, {to_gpu(sun)}, kGround, kSize, 1.0f);
  frame.boxes_apart = glm::uvec4(2, 2, 0, 0);
  for (int k = 0; k < 2; ++k) {
    const float y = k == 0 ? -1.5f : 1.5f;
    frame.changed_casters[2 * k] = frame.moved_instances[2 * k] = glm::vec4(-0.5f, y - 0.4f, 2.0f, 1.0f);
    frame.changed_casters[2 * k + 1] = frame.moved_instances[2 * k + 1] = glm::vec4(0.5f, y + 0.4f, 3.0f, 1.0f);
  }
  const TileMask apart = change_on_screen(frame, {to_gpu(sun)}, kGround, kSize, 1.0f);
  for (float y : {-1.5f, 1.5f}) {
    EXPECT_TRUE(apart.holds(seen_at(0.0f, y))) << "the caster at y = " << y;
    EXPECT_TRUE(apart.holds(seen_at(2.5f, y))) << "its shadow";
    EXPECT_TRUE(together.holds(seen_at(2.5f, y)));
  }
  for (float x : {0.0f, 2.5f}) {
    EXPECT_TRUE(together.holds(seen_at(x, 0.0f)));
    EXPECT_FALSE(apart.holds(seen_at(x, 0.0f))) << "the ground between the two, at x = " << x;
  }
  std::printf("share of the image: each caster's box %.3f, one box %.3f\n", apart.share(), together.share());
}

// The boxes the renderer puts apart (GpuScene::Changes): each changed
// instance's own, grown over its old and new places, while they are at most
// kMaxShadowMovers; past that none, and the union stands for them all.
TEST(BoxesApart, EachInstanceGrowsItsOwnBoxUntilTheyAreTooMany) {
  BoxesApart apart;
  apart.grow(3, {{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}});  // (where it was)
  apart.grow(5, {{8.0f, 0.0f, 0.0f}, {9.0f, 1.0f, 1.0f}});
  apart.grow(3, {{2.0f, 0.0f, 0.0f}, {3.0f, 1.0f, 1.0f}});  // (and where it is)
  ASSERT_EQ(apart.boxes.size(), 2u);
  EXPECT_FALSE(apart.many);
  EXPECT_EQ(apart.boxes[0].first, 3u);
  EXPECT_EQ(apart.boxes[0].second.lo.x, 0.0f);
  EXPECT_EQ(apart.boxes[0].second.hi.x, 3.0f);
  EXPECT_EQ(apart.boxes[1].second.lo.x, 8.0f) << "the other's box is its own";
  for (uint32_t i = 10; apart.boxes.size() < gpu::kMaxShadowMovers; ++i) apart.grow(i, {{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}});
  EXPECT_FALSE(apart.many);
  apart.grow(100, {{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}});
  EXPECT_TRUE(apart.many);
  EXPECT_TRUE(apart.boxes.empty());
  apart.grow(3, {{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}});
  EXPECT_TRUE(apart.boxes.empty()) << "once too many, none is kept apart";
}

TEST(ScreenRegion, NothingChangedIsEmpty) {
  gpu::FrameData frame{};
  frame.steady_world_to_clip = top_view();
  Light sun;
  EXPECT_TRUE(change_on_screen(frame, {to_gpu(sun)}, kGround, kSize, 1.0f).is_empty());
}

}  // namespace
}  // namespace rtsdf
