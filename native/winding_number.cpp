#include "winding_number.h"

#include <cmath>

namespace rtsdf {

std::vector<gpu::WindingDipole> winding_dipoles(const Bvh& bvh, const Mesh& mesh, const Pieces& pieces) {
  struct Sum {
    glm::dvec3 normal{0.0};
    glm::dvec3 weighted_centre{0.0};  // area * centre, summed
    double area = 0.0;
  };
  std::vector<Sum> sums(bvh.nodes.size());
  std::vector<gpu::WindingDipole> dipoles(bvh.nodes.size());
  auto corner = [&](uint32_t triangle, int k) { return glm::dvec3(mesh.positions[mesh.indices[3 * triangle + k]]); };
  // Children follow their parent in the node array: backwards, every child is done before its parent.
  for (size_t n = bvh.nodes.size(); n-- > 0;) {
    const BvhBuildNode& node = bvh.nodes[n];
    Sum& sum = sums[n];
    const bool leaf = node.count > 0;
    auto counts = [&](uint32_t i) { return pieces.thickness[bvh.order[i]] > 0.0f; };
    if (leaf) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        if (!counts(i)) continue;
        const uint32_t t = bvh.order[i];
        const glm::dvec3 area_vector = (pieces.faces_in[t] ? -0.5 : 0.5) *
                                       glm::cross(corner(t, 1) - corner(t, 0), corner(t, 2) - corner(t, 0));
        const double area = glm::length(area_vector);
        sum.normal += area_vector;
        sum.weighted_centre += area * (corner(t, 0) + corner(t, 1) + corner(t, 2)) / 3.0;
        sum.area += area;
      }
    } else {
      for (uint32_t child : {node.first, node.first + 1}) {
        sum.normal += sums[child].normal;
        sum.weighted_centre += sums[child].weighted_centre;
        sum.area += sums[child].area;
      }
    }
    const glm::dvec3 centre = sum.area > 0.0 ? sum.weighted_centre / sum.area : glm::dvec3(0.0);
    // The ball about the centre: over a leaf's corners, or around its children's balls.
    double radius = 0.0;
    if (leaf) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i)
        for (int k = 0; k < 3 && counts(i); ++k) radius = std::max(radius, glm::length(corner(bvh.order[i], k) - centre));
    } else {
      for (uint32_t child : {node.first, node.first + 1})
        if (sums[child].area > 0.0)
          radius = std::max(radius, glm::length(glm::dvec3(dipoles[child].centre) - centre) + dipoles[child].centre.w);
    }
    // (radius rounded up, so that float centres still lie within it)
    dipoles[n].centre = glm::vec4(centre, float(radius * (1.0 + 1e-6)));
    dipoles[n].normal = glm::vec4(sum.normal, float(sum.area));
  }
  return dipoles;
}

double winding_number(const Mesh& mesh, const Pieces& pieces, glm::vec3 p) {
  double solid_angle = 0.0;
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    if (!(pieces.thickness[t] > 0.0f)) continue;
    // Van Oosterom and Strackee's formula for the triangle's signed solid angle.
    const glm::dvec3 a = glm::dvec3(mesh.positions[mesh.indices[3 * t]] - p);
    const glm::dvec3 b = glm::dvec3(mesh.positions[mesh.indices[3 * t + 1]] - p);
    const glm::dvec3 c = glm::dvec3(mesh.positions[mesh.indices[3 * t + 2]] - p);
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    solid_angle += (pieces.faces_in[t] ? -2.0 : 2.0) * std::atan2(glm::dot(a, glm::cross(b, c)),
                                    la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb);
  }
  return solid_angle / (4.0 * M_PI);
}

}  // namespace rtsdf
