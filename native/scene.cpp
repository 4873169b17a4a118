#include "scene.h"

#include <cmath>
#include <limits>

#include "error.h"

namespace rtsdf {

size_t Scene::triangle_count() const {
  size_t count = 0;
  for (const Instance& instance : instances)
    if (instance.mesh < meshes.size()) count += meshes[instance.mesh].triangle_count();
  return count;
}

void Scene::validate() const {
  for (const Mesh& mesh : meshes) {
    const std::string label = "mesh '" + mesh.name + "'";
    if (mesh.indices.size() % 3 != 0) throw Error(label + " has an index count that is not a multiple of 3");
    for (const glm::vec3& p : mesh.positions)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw Error(label + " has NaN or infinite vertex coordinates");
    for (uint32_t index : mesh.indices)
      if (index >= mesh.positions.size()) throw Error(label + " has a triangle index past its vertex count");
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
      throw Error(label + " has a normal count different from its vertex count");
  }
  for (const Instance& instance : instances) {
    if (instance.mesh >= meshes.size()) throw Error("an instance refers to a mesh that does not exist");
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(instance.object_to_world[c][r]))
          throw Error("an instance of mesh '" + meshes[instance.mesh].name + "' has a NaN or infinite transform");
  }
  if (triangle_count() == 0) throw Error("the scene has no triangles");
  Bounds bounds = world_bounds();
  glm::vec3 extent = bounds.extent();
  if (!std::isfinite(extent.x) || !std::isfinite(extent.y) || !std::isfinite(extent.z))
    throw Error("the scene's bounds are not finite: coordinates are too large");
  if (std::max(extent.x, std::max(extent.y, extent.z)) <= 0.0f)
    throw Error("the scene has zero extent: every triangle is degenerate");
}

Bounds Scene::world_bounds() const {
  std::vector<uint32_t> all(instances.size());
  for (uint32_t i = 0; i < all.size(); ++i) all[i] = i;
  return world_bounds(all);
}

Bounds Scene::world_bounds(const std::vector<uint32_t>& instance_indices) const {
  const float inf = std::numeric_limits<float>::infinity();
  Bounds bounds{glm::vec3(inf), glm::vec3(-inf)};
  for (uint32_t i : instance_indices) {
    const Instance& instance = instances[i];
    const Mesh& mesh = meshes[instance.mesh];
    if (mesh.indices.empty()) continue;
    for (uint32_t index : mesh.indices) {
      glm::vec3 p = glm::vec3(instance.object_to_world * glm::vec4(mesh.positions[index], 1.0f));
      bounds.lo = glm::min(bounds.lo, p);
      bounds.hi = glm::max(bounds.hi, p);
    }
  }
  return bounds;
}

Scene single_mesh_scene(Mesh mesh) {
  Scene scene;
  scene.meshes.push_back(std::move(mesh));
  scene.instances.push_back(Instance{0, glm::mat4(1.0f)});
  return scene;
}

}  // namespace rtsdf
