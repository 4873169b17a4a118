#include "shadow_casters.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rtsdf {

namespace {

constexpr float kFlatness = 0.01f;  // thickness / size below which an instance counts as flat

struct Extent {
  float lo = std::numeric_limits<float>::infinity();
  float hi = -std::numeric_limits<float>::infinity();
};

// The instance's world vertices (each once, used by a triangle).
std::vector<glm::vec3> world_vertices(const Scene& scene, const Instance& instance) {
  const Mesh& mesh = scene.meshes[instance.mesh];
  std::vector<uint8_t> used(mesh.positions.size(), 0);
  for (uint32_t index : mesh.indices) used[index] = 1;
  std::vector<glm::vec3> out;
  for (size_t v = 0; v < mesh.positions.size(); ++v)
    if (used[v]) out.emplace_back(instance.object_to_world * glm::vec4(mesh.positions[v], 1.0f));
  return out;
}

Extent extent_along(const std::vector<glm::vec3>& points, glm::vec3 axis) {
  Extent e;
  for (const glm::vec3& p : points) {
    const float s = glm::dot(p, axis);
    e.lo = std::min(e.lo, s), e.hi = std::max(e.hi, s);
  }
  return e;
}

// Directions along which a flat instance may be thin: the world axes and the
// normal of its largest triangle (for tilted planes).
std::vector<glm::vec3> candidate_normals(const Scene& scene, const Instance& instance) {
  std::vector<glm::vec3> normals{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const Mesh& mesh = scene.meshes[instance.mesh];
  glm::vec3 largest(0.0f);
  float largest_area = 0.0f;
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    glm::vec3 corner[3];
    for (int k = 0; k < 3; ++k)
      corner[k] = glm::vec3(instance.object_to_world * glm::vec4(mesh.positions[mesh.indices[3 * t + k]], 1.0f));
    const glm::vec3 n = glm::cross(corner[1] - corner[0], corner[2] - corner[0]);
    const float area = glm::length(n);
    if (area > largest_area) largest_area = area, largest = n / area;
  }
  if (largest_area > 0.0f) normals.push_back(largest);
  return normals;
}

// Whether every light lies strictly on the side of the plane dot(x, n) = offset that n points to.
bool lights_in_front(const std::vector<Light>& lights, glm::vec3 n, float offset) {
  for (const Light& light : lights) {
    if (light.type == LightType::Sun) {
      if (!(glm::dot(-light.direction, n) > 0.0f)) return false;
    } else if (!(glm::dot(light.position, n) - offset > light.radius)) {
      return false;
    }
  }
  return true;
}

}  // namespace

std::vector<uint8_t> find_shadow_casters(const Scene& scene, const std::vector<Light>& lights) {
  const size_t count = scene.instances.size();
  std::vector<uint8_t> casters(count, 0);
  std::vector<std::vector<glm::vec3>> vertices(count);
  for (size_t i = 0; i < count; ++i) {
    casters[i] = scene.instances[i].casts_shadow ? 1 : 0;
    if (casters[i]) vertices[i] = world_vertices(scene, scene.instances[i]);
  }
  for (size_t i = 0; i < count; ++i) {
    if (!casters[i] || vertices[i].empty()) continue;
    const Bounds box = [&] {
      Bounds b{glm::vec3(std::numeric_limits<float>::infinity()), glm::vec3(-std::numeric_limits<float>::infinity())};
      for (const glm::vec3& p : vertices[i]) b.lo = glm::min(b.lo, p), b.hi = glm::max(b.hi, p);
      return b;
    }();
    const float size = glm::length(box.extent());
    const float tolerance = 1e-3f * size;  // objects resting on the ground may touch it or sink in a little
    for (glm::vec3 n : candidate_normals(scene, scene.instances[i])) {
      const Extent own = extent_along(vertices[i], n);
      if (own.hi - own.lo > kFlatness * size) continue;
      for (float side : {1.0f, -1.0f}) {
        // The outer face: the plane through the flat instance's extreme point along side * n.
        const glm::vec3 outward = side * n;
        const float offset = side > 0.0f ? own.hi : -own.lo;
        bool others_in_front = true;
        for (size_t j = 0; j < count && others_in_front; ++j) {
          if (j == i || !scene.instances[j].casts_shadow) continue;  // order-independent: the flags, not the result
          for (const glm::vec3& p : vertices[j])
            if (glm::dot(p, outward) - offset < -tolerance) {
              others_in_front = false;
              break;
            }
        }
        if (others_in_front && lights_in_front(lights, outward, offset)) {
          casters[i] = 0;
          break;
        }
      }
      if (!casters[i]) break;
    }
  }
  return casters;
}

std::vector<Bounds> sky_blockers(const Scene& scene, const std::vector<uint32_t>& casters, size_t max_count) {
  std::vector<std::pair<float, Bounds>> found;  // (area, box)
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    if (!scene.instances[i].casts_shadow || std::find(casters.begin(), casters.end(), i) != casters.end()) continue;
    const Bounds box = scene.world_bounds({i});
    if (box.is_empty()) continue;
    const glm::vec3 e = box.extent();
    const float size = glm::max(e.x, glm::max(e.y, e.z));
    const int thin = e.x <= e.y && e.x <= e.z ? 0 : e.y <= e.z ? 1 : 2;
    if (e[thin] > kFlatness * size) continue;
    found.push_back({e[(thin + 1) % 3] * e[(thin + 2) % 3], box});
  }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<Bounds> boxes;
  for (size_t k = 0; k < found.size() && k < max_count; ++k) boxes.push_back(found[k].second);
  return boxes;
}

}  // namespace rtsdf
