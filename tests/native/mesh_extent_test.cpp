// MeshExtent against every vertex transformed: the same bounds and extents,
// for shapes whose extremes fall in different cells, under rotation,
// non-uniform and negative scale. And placed_mesh, the scene's triangles in
// world space as one mesh.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <random>

#include "mesh_extent.h"
#include "reference/shapes.h"

namespace rtsdf {
namespace {

glm::vec2 brute_extent(const Mesh& mesh, const glm::mat4& m, glm::vec3 n) {
  glm::vec2 e(1e30f, -1e30f);
  for (uint32_t index : mesh.indices) {
    const float s = glm::dot(glm::vec3(m * glm::vec4(mesh.positions[index], 1.0f)), n);
    e = {std::min(e.x, s), std::max(e.y, s)};
  }
  return e;
}

TEST(MeshExtent, MatchesEveryVertexTransformed) {
  Mesh bumpy = reference::uv_sphere({0.3f, -0.2f, 0.1f}, 1.0f, 40);
  for (size_t v = 0; v < bumpy.positions.size(); ++v) bumpy.positions[v] *= 1.0f + 0.3f * std::sin(7.0f * float(v));
  Mesh unused_far = reference::box({-1, -1, -1}, {1, 2, 0.5f});
  unused_far.positions.push_back({100, 100, 100});  // no triangle uses it: no extent
  std::mt19937 random(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (const Mesh& mesh : {bumpy, unused_far, reference::sheet({-3, -1}, {2, 4}, 0.5f)}) {
    const MeshExtent extent(mesh);
    ASSERT_FALSE(extent.empty());
    for (int trial = 0; trial < 20; ++trial) {
      glm::mat4 m = glm::translate(glm::mat4(1.0f), {5 * u(random), 5 * u(random), 5 * u(random)});
      m = glm::rotate(m, 3.0f * u(random), glm::normalize(glm::vec3(u(random), u(random), u(random)) + 0.01f));
      m = glm::scale(m, {2.0f * u(random), 0.5f + u(random), 3.0f});
      const glm::vec3 n = glm::normalize(glm::vec3(u(random), u(random), u(random)) + 0.01f);
      const glm::vec2 fast = extent.placed_extent(m, n), slow = brute_extent(mesh, m, n);
      EXPECT_NEAR(fast.x, slow.x, 1e-4f);
      EXPECT_NEAR(fast.y, slow.y, 1e-4f);
      const Bounds box = extent.placed_bounds(m);
      for (int k = 0; k < 3; ++k) {
        glm::vec3 axis(0.0f);
        axis[k] = 1.0f;
        const glm::vec2 along = brute_extent(mesh, m, axis);
        EXPECT_NEAR(box.lo[k], along.x, 1e-4f);
        EXPECT_NEAR(box.hi[k], along.y, 1e-4f);
      }
    }
  }
}

TEST(MeshExtent, EmptyMeshHasNoBounds) {
  Mesh empty;
  empty.positions = {{0, 0, 0}, {1, 1, 1}};
  const MeshExtent extent(empty);
  const MeshExtent huge(reference::single_triangle({-3e38f, 0, 0}, {3e38f, 0, 0}, {0, 1, 0}));  // a size past float range
  EXPECT_EQ(huge.support({1, 0, 0}), 3e38f);
  EXPECT_TRUE(extent.empty());
  EXPECT_TRUE(extent.placed_bounds(glm::mat4(1.0f)).is_empty());
}

// Two instances of a box, one of them mirrored: every corner where its
// instance puts it, and every face turned out of the placed box as it is
// out of the box it was made from.
TEST(PlacedMesh, PlacesEveryInstanceAndKeepsItsFacesFacingOut) {
  Scene scene;
  scene.meshes.push_back(reference::box({-1, -1, -1}, {1, 1, 1}));
  const glm::mat4 moved = glm::translate(glm::mat4(1.0f), glm::vec3(5, 0, 0));
  const glm::mat4 mirrored = glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(-5, 0, 0)), glm::vec3(-1, 2, 1));
  scene.instances = {Instance{0, moved}, Instance{0, mirrored}};
  const Mesh placed = placed_mesh(scene);
  const Mesh& box = scene.meshes[0];
  ASSERT_EQ(placed.positions.size(), 2 * box.positions.size());
  ASSERT_EQ(placed.triangle_count(), 2 * box.triangle_count());
  for (size_t v = 0; v < box.positions.size(); ++v) {
    EXPECT_EQ(placed.positions[v], glm::vec3(moved * glm::vec4(box.positions[v], 1.0f)));
    EXPECT_EQ(placed.positions[box.positions.size() + v], glm::vec3(mirrored * glm::vec4(box.positions[v], 1.0f)));
  }
  for (size_t t = 0; t < placed.triangle_count(); ++t) {
    const glm::vec3 a = placed.positions[placed.indices[3 * t]], b = placed.positions[placed.indices[3 * t + 1]],
                    c = placed.positions[placed.indices[3 * t + 2]];
    const glm::vec3 centre = t < box.triangle_count() ? glm::vec3(5, 0, 0) : glm::vec3(-5, 0, 0);
    EXPECT_GT(glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0f - centre), 0.0f) << "triangle " << t;
  }
}

}  // namespace
}  // namespace rtsdf
