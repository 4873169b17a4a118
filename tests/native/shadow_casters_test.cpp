// Which instances go into the SDFs: flat receivers that cannot shadow anything
// are left out, everything that might occlude a light stays.
#include "shadow_casters.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "reference/shapes.h"

namespace rtsdf {
namespace {

Light sun_towards(glm::vec3 direction) {
  Light sun;
  sun.type = LightType::Sun;
  sun.direction = direction;
  return sun;
}

Light point_at(glm::vec3 position, float radius = 0.1f) {
  Light light;
  light.type = LightType::Point;
  light.position = position;
  light.radius = radius;
  return light;
}

// A 20 x 20 ground at z = 0 (instance 0) with a unit box resting on it (instance 1).
Scene box_on_ground(const Mesh& ground) {
  Scene scene;
  scene.meshes = {ground, reference::box({-0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 1.0f})};
  scene.instances = {{0, glm::mat4(1.0f)}, {1, glm::mat4(1.0f)}};
  return scene;
}

const Mesh kGroundSheet = reference::sheet({-10, -10}, {10, 10}, 0.0f);

TEST(ShadowCasters, GroundUnderObjectsLitFromAboveIsOnlyAReceiver) {
  const Scene scene = box_on_ground(kGroundSheet);
  EXPECT_EQ(find_shadow_casters(scene, {sun_towards({0.3f, 0.2f, -1.0f})}), (std::vector<uint8_t>{0, 1}));
  EXPECT_EQ(find_shadow_casters(scene, {point_at({1, 2, 3})}), (std::vector<uint8_t>{0, 1}));
  // A thin slab as the ground (its top face at z = 0), and a lone ground.
  EXPECT_EQ(find_shadow_casters(box_on_ground(reference::box({-10, -10, -0.1f}, {10, 10, 0})),
                                {sun_towards({0, 0, -1})}),
            (std::vector<uint8_t>{0, 1}));
  EXPECT_EQ(find_shadow_casters(single_mesh_scene(kGroundSheet), {sun_towards({0, 0, -1})}),
            (std::vector<uint8_t>{0}));
}

// A caster that stands through the ground (a foot through the floor, motion
// capture's limbs, a trunk set into terrain) leaves it a receiver: what sinks
// behind lies under it, hidden from every view above. Sunk half its height,
// the box used to put a 20 x 20 ground into the SDF.
TEST(ShadowCasters, GroundWithACasterSunkThroughItIsOnlyAReceiver) {
  Scene scene = box_on_ground(kGroundSheet);
  scene.instances[1].object_to_world = glm::translate(glm::mat4(1.0f), glm::vec3(2, 3, -0.5f));
  EXPECT_EQ(find_shadow_casters(scene, {sun_towards({0.3f, 0.2f, -1.0f})}), (std::vector<uint8_t>{0, 1}));
  // Sunk beyond the ground's edge, its part below can be seen from the side: the ground stays.
  scene.instances[1].object_to_world = glm::translate(glm::mat4(1.0f), glm::vec3(9.8f, 0, -0.5f));
  EXPECT_EQ(find_shadow_casters(scene, {sun_towards({0.3f, 0.2f, -1.0f})}), (std::vector<uint8_t>{1, 1}));
  // A ground turned 45 degrees about its normal (its corners 14.1 out along the axes, its edges 10 out
  // along the diagonals): at (2, 3) the box sinks under it; at (8.5, 8.5), 12 out along a diagonal, it
  // sinks beyond its edge, though inside the world box around the ground.
  scene.instances[0].object_to_world = glm::rotate(glm::mat4(1.0f), glm::radians(45.0f), glm::vec3(0, 0, 1));
  scene.instances[1].object_to_world = glm::translate(glm::mat4(1.0f), glm::vec3(2, 3, -0.5f));
  EXPECT_EQ(find_shadow_casters(scene, {sun_towards({0.3f, 0.2f, -1.0f})}), (std::vector<uint8_t>{0, 1}));
  scene.instances[1].object_to_world = glm::translate(glm::mat4(1.0f), glm::vec3(8.5f, 8.5f, -0.5f));
  EXPECT_EQ(find_shadow_casters(scene, {sun_towards({0.3f, 0.2f, -1.0f})}), (std::vector<uint8_t>{1, 1}));
}

TEST(ShadowCasters, GroundThatCanBlockALightStays) {
  const Scene scene = box_on_ground(kGroundSheet);
  // A sun below the horizon: the ground hides it from the box.
  EXPECT_EQ(find_shadow_casters(scene, {sun_towards({0, 0.2f, 1.0f})}), (std::vector<uint8_t>{1, 1}));
  // A light under the ground, or one whose sphere reaches through it.
  EXPECT_EQ(find_shadow_casters(scene, {point_at({0, 0, -1})}), (std::vector<uint8_t>{1, 1}));
  EXPECT_EQ(find_shadow_casters(scene, {point_at({3, 0, 0.05f}, 0.1f)}), (std::vector<uint8_t>{1, 1}));
  // Geometry under the ground as well as over it.
  Scene below = scene;
  below.instances.push_back({1, glm::translate(glm::mat4(1.0f), glm::vec3(3, 0, -2))});
  EXPECT_EQ(find_shadow_casters(below, {sun_towards({0, 0, -1})}), (std::vector<uint8_t>{1, 1, 1}));
}

TEST(ShadowCasters, WallBetweenTheSunAndTheRoomStays) {
  // A wall in the plane x = 2 (flat, tilted through the rotation), the sun outside it at +x.
  Scene scene = box_on_ground(kGroundSheet);
  scene.meshes.push_back(reference::sheet({-1, -1}, {1, 1}, 0.0f));
  const glm::mat4 wall = glm::translate(glm::mat4(1.0f), glm::vec3(2, 0, 1)) *
                         glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(0, 1, 0));
  scene.instances.push_back({2, wall});
  const std::vector<uint8_t> casters = find_shadow_casters(scene, {sun_towards({-1, 0, -0.5f})});
  EXPECT_EQ(casters[2], 1) << "the wall shadows the room";
  EXPECT_EQ(casters[1], 1);
  EXPECT_EQ(casters[0], 0) << "the ground, with everything and the sun above it, still only receives";
}

TEST(ShadowCasters, TiltedGroundIsFoundThroughItsOwnNormal) {
  Scene scene = box_on_ground(kGroundSheet);
  const glm::mat4 tilt = glm::rotate(glm::mat4(1.0f), glm::radians(20.0f), glm::vec3(1, 1, 0));
  for (Instance& instance : scene.instances) instance.object_to_world = tilt;
  EXPECT_EQ(find_shadow_casters(scene, {sun_towards(glm::mat3(tilt) * glm::vec3(0.2f, 0.1f, -1.0f))}),
            (std::vector<uint8_t>{0, 1}));
}

TEST(ShadowCasters, ObjectsWithShadowsTurnedOffAreLeftOut) {
  Scene scene = box_on_ground(kGroundSheet);
  const std::vector<Light> below{sun_towards({0, 0, 1})};  // the ground would hide it from the box
  scene.instances[1].casts_shadow = false;
  // The box no longer counts as geometry the ground could shadow.
  EXPECT_EQ(find_shadow_casters(scene, below), (std::vector<uint8_t>{0, 0}));
  scene.instances[1].casts_shadow = true;
  scene.instances[0].casts_shadow = false;
  EXPECT_EQ(find_shadow_casters(scene, below), (std::vector<uint8_t>{0, 1}));
}

}  // namespace
}  // namespace rtsdf

namespace rtsdf {
namespace {

// The flat receivers left out of the SDFs that still hide the sky: the
// ground's box, not a caster's, nor an instance whose shadows are off.
TEST(ShadowCasters, SkyBlockersAreTheGroundsLeftOut) {
  Scene scene;
  scene.meshes = {reference::sheet({-10, -10}, {10, 10}, 0.0f), reference::box({-0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 1.0f})};
  scene.instances = {{0, glm::mat4(1.0f)}, {1, glm::mat4(1.0f)}};
  std::vector<Bounds> blockers = sky_blockers(scene, mesh_extents(scene), {1}, 8);
  ASSERT_EQ(blockers.size(), 1u);
  EXPECT_EQ(blockers[0].lo, glm::vec3(-10, -10, 0));
  EXPECT_EQ(blockers[0].hi, glm::vec3(10, 10, 0));
  EXPECT_TRUE(sky_blockers(scene, mesh_extents(scene), {0, 1}, 8).empty()) << "a ground in the SDF blocks through the SDF";
  scene.instances[0].casts_shadow = false;
  EXPECT_TRUE(sky_blockers(scene, mesh_extents(scene), {1}, 8).empty()) << "an object that casts no shadow hides no sky";
  // A sheet tilted 45 degrees: its box is no thin slab.
  scene.instances[0].casts_shadow = true;
  scene.instances[0].object_to_world = glm::rotate(glm::mat4(1.0f), glm::radians(45.0f), glm::vec3(1, 0, 0));
  EXPECT_TRUE(sky_blockers(scene, mesh_extents(scene), {1}, 8).empty());
  EXPECT_TRUE(sky_blockers(scene, mesh_extents(scene), {1}, 0).empty());
}

}  // namespace
}  // namespace rtsdf
