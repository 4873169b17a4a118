#include "mesh_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace rtsdf {

namespace {

constexpr int kProbePoints = 256;
constexpr float kNoHit = std::numeric_limits<float>::infinity();

struct Triangle {
  glm::vec3 a, ab, ac;
};

// Distance along dir from o to the nearest triangle of the BVH but `skip`
// (Moller-Trumbore against the leaves the ray's slab test reaches).
float nearest_hit(const Bvh& bvh, const std::vector<Triangle>& triangles, glm::vec3 o, glm::vec3 dir, uint32_t skip) {
  const glm::vec3 inv = 1.0f / glm::vec3(std::abs(dir.x) > 1e-20f ? dir.x : 1e-20f,
                                         std::abs(dir.y) > 1e-20f ? dir.y : 1e-20f,
                                         std::abs(dir.z) > 1e-20f ? dir.z : 1e-20f);
  float best = kNoHit;
  uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const BvhBuildNode& node = bvh.nodes[stack[--top]];
    const glm::vec3 t0 = (node.box.lo - o) * inv, t1 = (node.box.hi - o) * inv;
    const glm::vec3 near = glm::min(t0, t1), far = glm::max(t0, t1);
    const float enter = std::max(std::max(near.x, near.y), std::max(near.z, 0.0f));
    const float leave = std::min(std::min(far.x, far.y), std::min(far.z, best));
    if (enter > leave) continue;
    if (node.count == 0) {
      if (top + 2 > 64) continue;  // (deeper than any binned SAH tree of a real mesh)
      stack[top++] = node.first;
      stack[top++] = node.first + 1;
      continue;
    }
    for (uint32_t k = node.first; k < node.first + node.count; ++k) {
      const uint32_t index = bvh.order[k];
      if (index == skip) continue;
      const Triangle& tri = triangles[index];
      const glm::vec3 p = glm::cross(dir, tri.ac);
      const float det = glm::dot(tri.ab, p);
      if (std::abs(det) < 1e-20f) continue;
      const float inv_det = 1.0f / det;
      const glm::vec3 s = o - tri.a;
      const float u = glm::dot(s, p) * inv_det;
      if (u < 0.0f || u > 1.0f) continue;
      const glm::vec3 q = glm::cross(s, tri.ab);
      const float v = glm::dot(dir, q) * inv_det;
      if (v < 0.0f || u + v > 1.0f) continue;
      const float t = glm::dot(tri.ac, q) * inv_det;
      if (t > 0.0f && t < best) best = t;
    }
  }
  return best;
}

}  // namespace

float mesh_feature_size(const Mesh& mesh, const Bvh& bvh) {
  const size_t count = mesh.triangle_count();
  if (count == 0) return kNoHit;
  std::vector<Triangle> triangles(count);
  std::vector<double> cumulative_area(count);
  double area = 0.0;
  glm::vec3 lo(kNoHit), hi(-kNoHit);
  for (size_t t = 0; t < count; ++t) {
    const glm::vec3 a = mesh.positions[mesh.indices[3 * t]], b = mesh.positions[mesh.indices[3 * t + 1]],
                    c = mesh.positions[mesh.indices[3 * t + 2]];
    triangles[t] = {a, b - a, c - a};
    area += 0.5 * double(glm::length(glm::cross(b - a, c - a)));
    cumulative_area[t] = area;
    lo = glm::min(lo, glm::min(a, glm::min(b, c)));
    hi = glm::max(hi, glm::max(a, glm::max(b, c)));
  }
  if (!(area > 0.0) || !std::isfinite(area)) return kNoHit;
  const float offset = 1e-5f * glm::length(hi - lo);  // (off the sample's own plane)
  std::vector<float> sizes;
  sizes.reserve(kProbePoints);
  for (int k = 0; k < kProbePoints; ++k) {
    // Stratified by area: the triangle holding the (k + 1/2)-th share, at its centroid.
    const double at = (k + 0.5) / kProbePoints * area;
    const uint32_t t = uint32_t(std::lower_bound(cumulative_area.begin(), cumulative_area.end(), at) -
                                cumulative_area.begin());
    const Triangle& tri = triangles[std::min<size_t>(t, count - 1)];
    const glm::vec3 normal = glm::cross(tri.ab, tri.ac);
    if (!(glm::dot(normal, normal) > 0.0f)) continue;
    const glm::vec3 n = glm::normalize(normal), centre = tri.a + (tri.ab + tri.ac) * (1.0f / 3.0f);
    float size = kNoHit;
    for (float side : {1.0f, -1.0f})
      size = std::min(size, offset + nearest_hit(bvh, triangles, centre + side * offset * n, side * n, t));
    sizes.push_back(size);
  }
  if (sizes.empty()) return kNoHit;
  std::sort(sizes.begin(), sizes.end());
  return sizes[sizes.size() / 4];  // (+infinity where fewer than a quarter met the mesh)
}

float detail_scale(float feature_size, float longest, int resolution) {
  if (!(feature_size > 0.0f) || !std::isfinite(feature_size) || !(longest > 0.0f) || resolution <= 0) {
    return feature_size == 0.0f ? kMaxDetailScale : 1.0f;  // (0: faces on top of each other: as thin as it gets)
  }
  const float voxel = longest / float(resolution);
  return std::clamp(kVoxelsAcrossFeature * voxel / feature_size, 1.0f, kMaxDetailScale);
}

}  // namespace rtsdf
