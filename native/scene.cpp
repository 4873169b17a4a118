#include "scene.h"

#include <cmath>
#include <limits>
#include <numeric>

#include "error.h"
#include "mesh_extent.h"

namespace rtsdf {

size_t Scene::triangle_count() const {
  size_t count = 0;
  for (const Instance& instance : instances)
    if (instance.mesh < meshes.size()) count += meshes[instance.mesh].triangle_count();
  return count;
}

void Scene::validate_mesh(const Mesh& mesh) {
  const std::string label = "mesh '" + mesh.name + "'";
  if (mesh.indices.size() % 3 != 0) throw Error(label + " has an index count that is not a multiple of 3");
  for (const glm::vec3& p : mesh.positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw Error(label + " has NaN or infinite vertex coordinates");
  for (uint32_t index : mesh.indices)
    if (index >= mesh.positions.size()) throw Error(label + " has a triangle index past its vertex count");
  if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
    throw Error(label + " has a normal count different from its vertex count");
  if (!mesh.materials.empty() && mesh.materials.size() != mesh.triangle_count())
    throw Error(label + " has a material index count different from its triangle count");
  if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size())
    throw Error(label + " has a UV count different from its vertex count");
  for (const glm::vec2& uv : mesh.uvs)
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) throw Error(label + " has NaN or infinite UVs");
  if (!mesh.colors.empty() && mesh.colors.size() != mesh.positions.size())
    throw Error(label + " has a vertex colour count different from its vertex count");
  for (const glm::vec3& c : mesh.colors)
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
      throw Error(label + " has NaN or infinite vertex colours");
}

void Scene::validate() const {
  for (const Mesh& mesh : meshes) validate_mesh(mesh);
  for (const Texture& texture : textures)
    if (texture.width < 1 || texture.height < 1 || texture.width > 16384 || texture.height > 16384 ||
        texture.texels.size() != size_t(texture.width) * size_t(texture.height))
      throw Error("image '" + texture.name + "' has a size out of range or a texel count that does not match it");
  for (const Instance& instance : instances) {
    if (instance.mesh >= meshes.size()) throw Error("an instance refers to a mesh that does not exist");
    for (const Material& material : instance.materials)
      if (material.texture >= int(textures.size()))
        throw Error("a material of mesh '" + meshes[instance.mesh].name + "' refers to an image that does not exist");
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(instance.object_to_world[c][r]))
          throw Error("an instance of mesh '" + meshes[instance.mesh].name + "' has a NaN or infinite transform");
  }
  validate_extent(world_bounds());
}

void Scene::validate_extent(const Bounds& bounds) const {
  if (triangle_count() == 0) throw Error("the scene has no triangles");
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
  // Only the meshes placed by these instances get an extent.
  std::vector<MeshExtent> extents(meshes.size());
  std::vector<uint8_t> built(meshes.size(), 0);
  for (uint32_t i : instance_indices)
    if (!built[instances[i].mesh]) extents[instances[i].mesh] = MeshExtent(meshes[instances[i].mesh]), built[instances[i].mesh] = 1;
  return world_bounds(instance_indices, extents);
}

Bounds Scene::world_bounds(const std::vector<uint32_t>& instance_indices, const std::vector<MeshExtent>& extents) const {
  const float inf = std::numeric_limits<float>::infinity();
  Bounds bounds{glm::vec3(inf), glm::vec3(-inf)};
  for (uint32_t i : instance_indices) {
    const Bounds b = extents[instances[i].mesh].placed_bounds(instances[i].object_to_world);
    if (b.is_empty()) continue;
    bounds.lo = glm::min(bounds.lo, b.lo);
    bounds.hi = glm::max(bounds.hi, b.hi);
  }
  return bounds;
}

Scene single_mesh_scene(Mesh mesh) {
  Scene scene;
  scene.meshes.push_back(std::move(mesh));
  scene.instances.push_back(Instance{0, glm::mat4(1.0f)});
  return scene;
}

Mesh placed_mesh(const Scene& scene) {
  Mesh placed;
  placed.positions.reserve(std::accumulate(scene.instances.begin(), scene.instances.end(), size_t(0),
                                           [&](size_t n, const Instance& i) { return n + scene.meshes[i.mesh].positions.size(); }));
  placed.indices.reserve(3 * scene.triangle_count());
  for (const Instance& instance : scene.instances) {
    const Mesh& mesh = scene.meshes[instance.mesh];
    const uint32_t base = uint32_t(placed.positions.size());
    for (const glm::vec3& p : mesh.positions) placed.positions.push_back(glm::vec3(instance.object_to_world * glm::vec4(p, 1.0f)));
    const bool mirrored = glm::determinant(glm::mat3(instance.object_to_world)) < 0.0f;
    for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3)
      for (int k : {0, mirrored ? 2 : 1, mirrored ? 1 : 2}) placed.indices.push_back(base + mesh.indices[i + k]);
  }
  return placed;
}

}  // namespace rtsdf
