#pragma once
// Bounding volume hierarchies for ray tracing on the device. One builder
// (binned SAH) serves both levels: triangles of one mesh (bottom level) and
// instances of meshes (top level).
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "scene.h"
#include "shaders/shared.h"

namespace rtsdf {

struct Aabb {
  glm::vec3 lo{1e30f};
  glm::vec3 hi{-1e30f};
  void grow(glm::vec3 p) { lo = glm::min(lo, p), hi = glm::max(hi, p); }
  void grow(const Aabb& b) { lo = glm::min(lo, b.lo), hi = glm::max(hi, b.hi); }
  float area() const {
    glm::vec3 e = glm::max(hi - lo, glm::vec3(0.0f));
    return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
};

// Flattened node, the layout the shaders read (see BvhNode in shaders/shared.h):
// count > 0: leaf holding primitives [first, first + count) of the BVH's order;
// count == 0: inner node whose children are nodes `first` and `first + 1`.
struct BvhBuildNode {
  Aabb box;
  uint32_t first = 0;
  uint32_t count = 0;
};

struct Bvh {
  std::vector<BvhBuildNode> nodes;  // nodes[0] is the root
  std::vector<uint32_t> order;      // primitive indices in leaf order
};

// Binned SAH (16 bins per axis), at most `max_leaf` primitives per leaf.
Bvh build_bvh(const std::vector<Aabb>& boxes, uint32_t max_leaf = 4);

// The nodes as the shaders read them (gpu::BvhNode), for a BVH whose nodes
// start at `node_offset` in their buffer and whose leaves' primitives start
// at `primitive_offset` in theirs.
std::vector<gpu::BvhNode> gpu_nodes(const Bvh& bvh, uint32_t node_offset = 0, uint32_t primitive_offset = 0);

// Bottom level of one mesh: triangles in object space.
Bvh build_mesh_bvh(const Mesh& mesh);

// The boxes of a mesh's bottom level made anew, leaves up, for the moved
// vertices of the triangles it was built over (a deformation keeps them and
// their order): the tree stays, at a fraction of a build's cost.
void refit_mesh_bvh(Bvh& bvh, const Mesh& mesh);

// The nodes' box areas summed, over the root's: a tree's cost to trace (the
// SAH's, up to constants). A refitted tree's grows as its mesh deforms away
// from the pose it was built for.
float bvh_cost(const Bvh& bvh);

}  // namespace rtsdf
