// A deformed mesh's refitted bottom level: the same tree with every box
// made anew (tight around its triangles and its children), and its cost
// (bvh_cost), which decides when the tree is built again.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

#include "bvh.h"
#include "reference/shapes.h"

namespace rtsdf {
namespace {

// The box of every corner of every triangle below `node`, gathered top down.
std::pair<glm::vec3, glm::vec3> corners_below(const Bvh& bvh, const Mesh& mesh, uint32_t node) {
  const BvhBuildNode& n = bvh.nodes[node];
  if (n.count == 0) {
    const auto [left_lo, left_hi] = corners_below(bvh, mesh, n.first);
    const auto [right_lo, right_hi] = corners_below(bvh, mesh, n.first + 1);
    return {glm::min(left_lo, right_lo), glm::max(left_hi, right_hi)};
  }
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (uint32_t i = n.first; i < n.first + n.count; ++i) {
    const uint32_t* corner = &mesh.indices[3 * size_t(bvh.order[i])];
    for (const uint32_t* c = corner; c != corner + 3; ++c) lo = glm::min(lo, mesh.positions[*c]), hi = glm::max(hi, mesh.positions[*c]);
  }
  return {lo, hi};
}

// Every node's box is exactly the box of the triangles below it.
void expect_tight(const Bvh& bvh, const Mesh& mesh) {
  for (uint32_t n = 0; n < bvh.nodes.size(); ++n) {
    const auto [lo, hi] = corners_below(bvh, mesh, n);
    ASSERT_EQ(bvh.nodes[n].box.lo, lo) << "node " << n;
    ASSERT_EQ(bvh.nodes[n].box.hi, hi) << "node " << n;
  }
}

// The sphere twisted about its axis and bulged: every vertex moves, the triangles stay.
Mesh twisted(Mesh mesh, float turns) {
  for (glm::vec3& p : mesh.positions) {
    const float angle = turns * p.z, c = std::cos(angle), s = std::sin(angle);
    p = glm::vec3(c * p.x - s * p.y, s * p.x + c * p.y, p.z) * (1.0f + 0.3f * p.z * p.z);
  }
  return mesh;
}

TEST(BvhRefit, KeepsTheTreeWithEveryBoxMadeAnew) {
  const Mesh sphere = reference::uv_sphere({0, 0, 0}, 1.0f, 32);
  Bvh bvh = build_mesh_bvh(sphere);
  const Bvh built = bvh;
  const Mesh deformed = twisted(sphere, 1.5f);
  refit_mesh_bvh(bvh, deformed);
  ASSERT_EQ(bvh.nodes.size(), built.nodes.size());
  EXPECT_EQ(bvh.order, built.order);
  for (size_t n = 0; n < bvh.nodes.size(); ++n) {
    EXPECT_EQ(bvh.nodes[n].first, built.nodes[n].first);
    EXPECT_EQ(bvh.nodes[n].count, built.nodes[n].count);
  }
  expect_tight(bvh, deformed);
  // (a refit of the shape it was built for gives back the built boxes)
  refit_mesh_bvh(bvh, sphere);
  expect_tight(bvh, sphere);
  for (size_t n = 0; n < bvh.nodes.size(); ++n) EXPECT_EQ(bvh.nodes[n].box.lo, built.nodes[n].box.lo);
}

TEST(BvhRefit, CostGrowsWhenTheTrianglesScatterNotWhenTheMeshOnlyScales) {
  const Mesh sphere = reference::uv_sphere({0, 0, 0}, 1.0f, 32);
  const Bvh built = build_mesh_bvh(sphere);
  const float built_cost = bvh_cost(built);
  EXPECT_GT(built_cost, 1.0f);

  Bvh scaled = built;
  Mesh larger = sphere;
  for (glm::vec3& p : larger.positions) p *= 3.0f;
  refit_mesh_bvh(scaled, larger);
  EXPECT_NEAR(bvh_cost(scaled), built_cost, 1e-3f * built_cost);

  // Vertices shuffled: every triangle spans the sphere, and so does every box.
  Bvh scattered = built;
  Mesh shuffled = sphere;
  std::mt19937 random(7);
  std::shuffle(shuffled.positions.begin(), shuffled.positions.end(), random);
  refit_mesh_bvh(scattered, shuffled);
  EXPECT_GT(bvh_cost(scattered), 3.0f * built_cost);
  // A tree built anew for it costs less again.
  EXPECT_LT(bvh_cost(build_mesh_bvh(shuffled)), bvh_cost(scattered));
}

}  // namespace
}  // namespace rtsdf
