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

// A mesh's largest triangle (object space): its normal (not normalized) and
// its shortest edge, along the outline of a rectangle's halves; both zero
// for a mesh without area.
struct LargestTriangle {
  glm::vec3 normal{0.0f}, shortest_edge{0.0f};
};

LargestTriangle largest_triangle(const Mesh& mesh) {
  LargestTriangle largest;
  float largest_area = 0.0f;
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    const glm::vec3* p = mesh.positions.data();
    const glm::vec3 a = p[mesh.indices[3 * t]], b = p[mesh.indices[3 * t + 1]], c = p[mesh.indices[3 * t + 2]];
    const glm::vec3 n = glm::cross(b - a, c - a);
    const float area = glm::length(n);
    if (area <= largest_area) continue;
    largest_area = area;
    largest.normal = n;
    largest.shortest_edge = b - a;
    for (glm::vec3 edge : {c - b, a - c})
      if (glm::dot(edge, edge) < glm::dot(largest.shortest_edge, largest.shortest_edge)) largest.shortest_edge = edge;
  }
  return largest;
}

// Directions along which a flat instance may be thin: the world axes and the
// placed normal of its mesh's largest triangle (for tilted planes; a flat
// mesh's triangles all share that normal, however it is placed).
std::vector<glm::vec3> candidate_normals(glm::vec3 largest_triangle_normal, const glm::mat4& object_to_world) {
  std::vector<glm::vec3> normals{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const glm::vec3 placed = glm::transpose(glm::inverse(glm::mat3(object_to_world))) * largest_triangle_normal;
  const float length = glm::length(placed);
  if (length > 0.0f && std::isfinite(length)) normals.push_back(placed / length);
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

// Whether another caster leaves the flat instance free to be only a
// receiver, with its outer face the plane dot(x, outward) = offset: it lies
// in front of that face (give or take `tolerance`), or it stands on it: it
// reaches in front, and what sinks behind lies within the flat instance's
// own extent across (a foot through a floor, a trunk in the ground). That
// part is then hidden under the flat instance from every view in front of
// it, and no path from a surface in front to a light in front passes there.
// (Only geometry wholly behind, or behind beyond its edge, can be a receiver
// there that it might shadow.) The extent across is measured along the flat
// instance's own outline (`edge`, placed: its largest triangle's shortest
// side) and across it, so that a ground turned about its normal is not taken
// for the larger box around it; a disc's is the square around it.
bool leaves_it_a_receiver(const MeshExtent& flat, const glm::mat4& flat_to_world, glm::vec3 edge,
                          const MeshExtent& other, const glm::mat4& other_to_world, glm::vec3 outward, float offset,
                          float tolerance) {
  const glm::vec2 along = other.placed_extent(other_to_world, outward);
  if (along.x - offset >= -tolerance) return true;
  if (along.y - offset <= tolerance) return false;
  const glm::vec3 in_plane = edge - glm::dot(edge, outward) * outward;
  const float length = glm::length(in_plane);
  if (!(length > 0.0f) || !std::isfinite(length)) return false;  // (no outline to measure along: it stays)
  const glm::vec3 t = in_plane / length, b = glm::cross(outward, t);
  for (glm::vec3 d : {t, b}) {
    const glm::vec2 own = flat.placed_extent(flat_to_world, d), theirs = other.placed_extent(other_to_world, d);
    if (theirs.x < own.x - tolerance || theirs.y > own.y + tolerance) return false;
  }
  return true;
}

}  // namespace

std::vector<uint8_t> find_shadow_casters(const Scene& scene, const std::vector<Light>& lights) {
  return find_shadow_casters(scene, mesh_extents(scene), lights);
}

std::vector<uint8_t> find_shadow_casters(const Scene& scene, const std::vector<MeshExtent>& extents,
                                         const std::vector<Light>& lights) {
  const size_t count = scene.instances.size();
  std::vector<uint8_t> casters(count, 0);
  for (size_t i = 0; i < count; ++i)
    casters[i] = scene.instances[i].casts_shadow && !extents[scene.instances[i].mesh].empty() ? 1 : 0;
  // Each mesh's largest triangle, found once however many instances it has.
  std::vector<LargestTriangle> largest;
  for (const Mesh& mesh : scene.meshes) largest.push_back(largest_triangle(mesh));
  for (size_t i = 0; i < count; ++i) {
    if (!casters[i]) continue;
    const Instance& instance = scene.instances[i];
    const MeshExtent& extent = extents[instance.mesh];
    const Bounds box = extent.placed_bounds(instance.object_to_world);
    const float size = glm::length(box.extent());
    const float tolerance = 1e-3f * size;  // (rounding: objects resting on the ground may touch it)
    const glm::vec3 edge = glm::mat3(instance.object_to_world) * largest[instance.mesh].shortest_edge;
    for (glm::vec3 n : candidate_normals(largest[instance.mesh].normal, instance.object_to_world)) {
      const glm::vec2 own = extent.placed_extent(instance.object_to_world, n);
      if (own.y - own.x > kFlatness * size) continue;
      for (float side : {1.0f, -1.0f}) {
        // The outer face: the plane through the flat instance's extreme point along side * n.
        const glm::vec3 outward = side * n;
        const float offset = side > 0.0f ? own.y : -own.x;
        bool others_in_front = true;
        for (size_t j = 0; j < count && others_in_front; ++j) {
          const Instance& other = scene.instances[j];
          if (j == i || !other.casts_shadow || extents[other.mesh].empty()) continue;  // the flags, not the result
          others_in_front = leaves_it_a_receiver(extent, instance.object_to_world, edge, extents[other.mesh],
                                                 other.object_to_world, outward, offset, tolerance);
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

std::vector<Bounds> sky_blockers(const Scene& scene, const std::vector<MeshExtent>& extents,
                                 const std::vector<uint32_t>& casters, size_t max_count) {
  std::vector<std::pair<float, Bounds>> found;  // (area, box)
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    if (!scene.instances[i].casts_shadow || std::binary_search(casters.begin(), casters.end(), i)) continue;
    const Bounds box = extents[scene.instances[i].mesh].placed_bounds(scene.instances[i].object_to_world);
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
