#include "shapes.h"

#include <cmath>
#include <utility>
#include <vector>

namespace rtsdf::reference {

Mesh uv_sphere(glm::vec3 center, float radius, int segments) {
  Mesh mesh;
  mesh.name = "sphere";
  const int rings = segments / 2;
  for (int r = 0; r <= rings; ++r) {
    float theta = float(M_PI) * float(r) / float(rings);
    for (int s = 0; s < segments; ++s) {
      float phi = 2.0f * float(M_PI) * float(s) / float(segments);
      mesh.positions.push_back(center + radius * glm::vec3(std::sin(theta) * std::cos(phi),
                                                           std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  }
  auto at = [&](int r, int s) { return uint32_t(r * segments + (s % segments)); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      if (r > 0) mesh.indices.insert(mesh.indices.end(), {at(r, s), at(r + 1, s), at(r, s + 1)});
      if (r < rings - 1) mesh.indices.insert(mesh.indices.end(), {at(r, s + 1), at(r + 1, s), at(r + 1, s + 1)});
    }
  return mesh;
}

Mesh box(glm::vec3 lo, glm::vec3 hi) {
  Mesh mesh;
  mesh.name = "box";
  for (int i = 0; i < 8; ++i)
    mesh.positions.emplace_back(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
  // Outward-facing (counter-clockwise seen from outside).
  mesh.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                  2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  return mesh;
}

Mesh cracked_box(glm::vec3 lo, glm::vec3 hi) {
  Mesh mesh = box(lo, hi);
  mesh.name = "cracked box";
  // The top face (z = hi: corners 4, 5, 6, 7) is remade around vertex 8, the
  // middle of its edge 4-5, which the side face y = lo still uses whole.
  mesh.positions.emplace_back(0.5f * (lo.x + hi.x), lo.y, hi.z);
  const std::vector<uint32_t> top = {4, 8, 6, 8, 5, 7, 8, 7, 6};
  mesh.indices.erase(mesh.indices.begin() + 6, mesh.indices.begin() + 12);
  mesh.indices.insert(mesh.indices.end(), top.begin(), top.end());
  return mesh;
}

Mesh inside_out(Mesh mesh) {
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
  return mesh;
}

Mesh sheet(glm::vec2 lo, glm::vec2 hi, float z) {
  Mesh mesh;
  mesh.name = "sheet";
  mesh.positions = {{lo.x, lo.y, z}, {hi.x, lo.y, z}, {hi.x, hi.y, z}, {lo.x, hi.y, z}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  return mesh;
}

Mesh single_triangle(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  Mesh mesh;
  mesh.name = "triangle";
  mesh.positions = {a, b, c};
  mesh.indices = {0, 1, 2};
  return mesh;
}

void append(Mesh& mesh, const Mesh& other) {
  uint32_t base = uint32_t(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), other.positions.begin(), other.positions.end());
  for (uint32_t i : other.indices) mesh.indices.push_back(base + i);
}

float box_distance(glm::vec3 p, glm::vec3 lo, glm::vec3 hi) {
  glm::vec3 center = 0.5f * (lo + hi), half = 0.5f * (hi - lo);
  glm::vec3 q = glm::abs(p - center) - half;
  return glm::length(glm::max(q, glm::vec3(0.0f))) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0f);
}

}  // namespace rtsdf::reference
