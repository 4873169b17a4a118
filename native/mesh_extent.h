#pragma once
// Exact extents of a placed mesh along any direction (its support
// function), for the bounds and flatness of many instances without visiting
// every instanced vertex: the mesh's vertices (those some triangle uses) are
// grouped into cells of a coarse grid, each with its box; a query bounds
// every cell by its box and reads the vertices only of cells that may hold
// the extreme. 1,000 instances of a 10,000-vertex mesh cost a few hundred
// box tests each instead of 10 million vertex transforms.
#include <vector>

#include "scene.h"

namespace rtsdf {

class MeshExtent {
 public:
  MeshExtent() = default;
  explicit MeshExtent(const Mesh& mesh);

  // No triangle uses any vertex: no extent along anything.
  bool empty() const { return points_.empty(); }
  // The largest dot(v, d) over the mesh's vertices v (object space); call only when not empty().
  float support(glm::vec3 d) const;
  // (lowest, highest) dot(p, n) over the world vertices p of the mesh placed by object_to_world.
  glm::vec2 placed_extent(const glm::mat4& object_to_world, glm::vec3 n) const;
  // The world box of the mesh placed by object_to_world: exact, as of its vertices (empty() for an empty mesh).
  Bounds placed_bounds(const glm::mat4& object_to_world) const;

 private:
  struct Cell {
    glm::vec3 centre, half;  // the box of the cell's vertices
    uint32_t first, count;   // its vertices in points_
  };
  std::vector<glm::vec3> points_;  // grouped by cell
  std::vector<Cell> cells_;
};

// One MeshExtent per mesh of the scene.
std::vector<MeshExtent> mesh_extents(const Scene& scene);

}  // namespace rtsdf
