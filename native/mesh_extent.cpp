#include "mesh_extent.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rtsdf {

namespace {

constexpr uint32_t kVerticesPerCell = 32;  // on average: few enough to read, enough to skip many at once

}  // namespace

MeshExtent::MeshExtent(const Mesh& mesh) {
  std::vector<uint8_t> used(mesh.positions.size(), 0);
  for (uint32_t index : mesh.indices) used[index] = 1;
  std::vector<glm::vec3> points;
  Bounds box{glm::vec3(std::numeric_limits<float>::infinity()), glm::vec3(-std::numeric_limits<float>::infinity())};
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    if (!used[v]) continue;
    points.push_back(mesh.positions[v]);
    box.lo = glm::min(box.lo, mesh.positions[v]), box.hi = glm::max(box.hi, mesh.positions[v]);
  }
  if (points.empty()) return;

  // A grid over the box with about kVerticesPerCell vertices a cell, fewer
  // cells along the box's short sides; vertices counting-sorted by cell.
  const glm::vec3 extent = box.extent();
  const float longest = std::max(extent.x, std::max(extent.y, extent.z));
  const float across = std::max(1.0f, std::round(std::cbrt(float(points.size()) / kVerticesPerCell)));
  glm::ivec3 dims(1);  // (one cell for coordinates so large that the box's size overflows)
  for (int k = 0; k < 3; ++k)
    if (longest > 0.0f && std::isfinite(longest))
      dims[k] = int(std::clamp(std::round(across * extent[k] / longest), 1.0f, across));
  auto cell_of = [&](const glm::vec3& p) {
    glm::ivec3 c(0);
    for (int k = 0; k < 3; ++k)
      if (dims[k] > 1) c[k] = std::clamp(int((p[k] - box.lo[k]) / extent[k] * float(dims[k])), 0, dims[k] - 1);
    return uint32_t(c.x + dims.x * (c.y + dims.y * c.z));
  };
  const uint32_t cell_count = uint32_t(dims.x * dims.y * dims.z);
  std::vector<uint32_t> start(cell_count + 1, 0);
  for (const glm::vec3& p : points) start[cell_of(p) + 1]++;
  for (uint32_t c = 0; c < cell_count; ++c) start[c + 1] += start[c];
  points_.resize(points.size());
  std::vector<uint32_t> next(start.begin(), start.end() - 1);
  for (const glm::vec3& p : points) points_[next[cell_of(p)]++] = p;

  for (uint32_t c = 0; c < cell_count; ++c) {
    if (start[c] == start[c + 1]) continue;
    glm::vec3 lo = points_[start[c]], hi = lo;
    for (uint32_t i = start[c]; i < start[c + 1]; ++i) lo = glm::min(lo, points_[i]), hi = glm::max(hi, points_[i]);
    cells_.push_back({0.5f * (lo + hi), 0.5f * (hi - lo), start[c], start[c + 1] - start[c]});
  }
}

float MeshExtent::support(glm::vec3 d) const {
  const glm::vec3 reach = glm::abs(d);
  auto bound = [&](const Cell& cell) { return glm::dot(cell.centre, d) + glm::dot(cell.half, reach); };
  auto exact = [&](const Cell& cell) {
    float best = -std::numeric_limits<float>::infinity();
    for (uint32_t i = cell.first; i < cell.first + cell.count; ++i) best = std::max(best, glm::dot(points_[i], d));
    return best;
  };
  // The most promising cell first, so that most others fall below what it holds.
  size_t top = 0;
  for (size_t c = 1; c < cells_.size(); ++c)
    if (bound(cells_[c]) > bound(cells_[top])) top = c;
  float best = exact(cells_[top]);
  for (size_t c = 0; c < cells_.size(); ++c)
    if (c != top && bound(cells_[c]) > best) best = std::max(best, exact(cells_[c]));
  return best;
}

glm::vec2 MeshExtent::placed_extent(const glm::mat4& object_to_world, glm::vec3 n) const {
  // dot(A v + t, n) = dot(v, A^T n) + dot(t, n)
  const glm::vec3 d = glm::transpose(glm::mat3(object_to_world)) * n;
  const float shift = glm::dot(glm::vec3(object_to_world[3]), n);
  return {shift - support(-d), shift + support(d)};
}

Bounds MeshExtent::placed_bounds(const glm::mat4& object_to_world) const {
  if (empty()) return Bounds::empty();
  Bounds bounds;
  for (int k = 0; k < 3; ++k) {
    glm::vec3 axis(0.0f);
    axis[k] = 1.0f;
    const glm::vec2 e = placed_extent(object_to_world, axis);
    bounds.lo[k] = e.x, bounds.hi[k] = e.y;
  }
  return bounds;
}

std::vector<MeshExtent> mesh_extents(const Scene& scene) {
  std::vector<MeshExtent> extents;
  extents.reserve(scene.meshes.size());
  for (const Mesh& mesh : scene.meshes) extents.emplace_back(mesh);
  return extents;
}

}  // namespace rtsdf
