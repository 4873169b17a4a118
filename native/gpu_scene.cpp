#include "gpu_scene.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <unordered_map>
#include <utility>

#include "error.h"
#include "mesh_topology.h"
#include "winding_number.h"
#include "shaders/shared.h"

namespace rtsdf {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

template <typename T>
vk::Buffer storage(const vk::Context& context, const std::vector<T>& data) {
  return vk::upload_buffer(context, data.data(), data.size() * sizeof(T), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
}

uint64_t next_scene_id() {
  static std::atomic<uint64_t> next{1};
  return next++;
}

}  // namespace

GpuScene::GpuScene(const vk::Context& context, const Scene& scene)
    : context_(context), id_(next_scene_id()), scene_(scene) {
  scene_.validate();
  extents_ = rtsdf::mesh_extents(scene_);
  mesh_versions_.assign(scene_.meshes.size(), 0);
  for (uint32_t i = 0; i < scene_.instances.size(); ++i)
    if (scene_.instances[i].casts_shadow) casters_.push_back(i);
  update_bounds();
  upload_raster();
  upload_materials();
}

void GpuScene::update_bounds() {
  bounds_ = casters_.empty() ? Bounds{} : scene_.world_bounds(casters_, extents_);
}

void GpuScene::mark_changed(uint32_t instance) {
  if (!std::binary_search(casters_.begin(), casters_.end(), instance)) return;
  const Bounds b = scene_.world_bounds({instance}, extents_);
  if (b.is_empty()) return;  // an empty mesh
  changes_.region = changes_.any ? Bounds{glm::min(changes_.region.lo, b.lo), glm::max(changes_.region.hi, b.hi)} : b;
  changes_.any = true;
}

GpuScene::Changes GpuScene::take_changes() {
  Changes taken = changes_;
  changes_ = Changes{false, false, Bounds{}};
  return taken;
}

void GpuScene::set_shadow_casters(const std::vector<uint8_t>& casters) {
  if (casters.size() != scene_.instances.size())
    throw Error("set_shadow_casters: expected " + std::to_string(scene_.instances.size()) + " flags");
  std::vector<uint32_t> indices;
  for (uint32_t i = 0; i < casters.size(); ++i)
    if (casters[i]) indices.push_back(i);
  if (indices == casters_) return;
  casters_ = std::move(indices);
  changes_.everything = true;
  update_bounds();
  if (has_ray_structures_) build_top_level();
}

const GpuScene::RayStructures& GpuScene::ray_structures() {
  if (casters_.empty()) throw Error("the scene has no shadow-casting geometry to trace");
  if (!has_ray_structures_) {
    Clock::time_point start = Clock::now();
    mesh_bvhs_.resize(scene_.meshes.size());
    pieces_.resize(scene_.meshes.size());
    for (uint32_t m = 0; m < scene_.meshes.size(); ++m) build_bottom_level(m);
    upload_bottom_levels();
    build_top_level();
    bvh_build_ms_ = ms_since(start);
    has_ray_structures_ = true;
  }
  return rays_;
}

GpuScene::RayTargets GpuScene::mesh_rays(uint32_t mesh) {
  const RayStructures& rays = ray_structures();
  if (mesh >= scene_.meshes.size()) throw Error("mesh_rays: no mesh " + std::to_string(mesh));
  mesh_tops_.resize(scene_.meshes.size());
  MeshTop& top = mesh_tops_[mesh];
  if (!top.top_nodes) {
    gpu::BvhNode root = gpu_nodes(mesh_bvhs_[mesh])[0];
    root.first = 0;
    root.count = 1;  // a leaf over the one instance
    gpu::RayInstance instance{};
    instance.world_to_object = instance.object_to_world = glm::mat4(1.0f);
    instance.blas_root = blas_roots_[mesh];
    top.top_nodes = storage(context_, std::vector<gpu::BvhNode>{root});
    top.instances = storage(context_, std::vector<gpu::RayInstance>{instance});
  }
  return {top.top_nodes, top.instances, rays.bottom_nodes, rays.triangles, rays.winding_dipoles};
}

Bounds GpuScene::mesh_bounds(uint32_t mesh) const {
  const Mesh& m = scene_.meshes.at(mesh);
  if (m.positions.empty()) return Bounds::empty();
  Bounds b{m.positions[0], m.positions[0]};
  for (const glm::vec3& p : m.positions) b.lo = glm::min(b.lo, p), b.hi = glm::max(b.hi, p);
  return b;
}

void GpuScene::upload_raster() {
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> uvs;
  std::vector<uint32_t> indices, slots;
  meshes_.clear();
  for (const Mesh& mesh : scene_.meshes) {
    meshes_.push_back({uint32_t(indices.size()), uint32_t(positions.size()), uint32_t(mesh.triangle_count())});
    // A vertex shared by faces of several material slots becomes one per slot
    // (the G-buffer takes the slot from the vertex, not the triangle: a
    // fragment shader that reads its primitive's index is 8x slower on lavapipe).
    std::vector<uint32_t> corner_vertex = mesh.indices;
    std::vector<uint32_t> vertex_source(mesh.positions.size()), vertex_slot(mesh.positions.size(), 0u);
    for (uint32_t v = 0; v < vertex_source.size(); ++v) vertex_source[v] = v;
    if (!mesh.materials.empty()) {
      std::unordered_map<uint64_t, uint32_t> split;
      std::vector<uint8_t> taken(mesh.positions.size(), 0);
      for (size_t c = 0; c < corner_vertex.size(); ++c) {
        const uint32_t v = mesh.indices[c], slot = mesh.materials[c / 3];
        if (!taken[v]) {
          taken[v] = 1;
          vertex_slot[v] = slot;
          split[(uint64_t(v) << 32) | slot] = v;
          continue;
        }
        auto [it, added] = split.try_emplace((uint64_t(v) << 32) | slot, uint32_t(vertex_source.size()));
        if (added) {
          vertex_source.push_back(v);
          vertex_slot.push_back(slot);
        }
        corner_vertex[c] = it->second;
      }
    }
    for (uint32_t source : vertex_source) {
      positions.push_back(mesh.positions[source]);
      normals.push_back(mesh.normals.empty() ? glm::vec3(0.0f) : mesh.normals[source]);
      uvs.push_back(mesh.uvs.empty() ? glm::vec2(0.0f) : mesh.uvs[source]);
    }
    slots.insert(slots.end(), vertex_slot.begin(), vertex_slot.end());
    indices.insert(indices.end(), corner_vertex.begin(), corner_vertex.end());
  }
  uvs_ = storage(context_, uvs);
  vertex_materials_ = storage(context_, slots);
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "positions are uploaded as packed floats");
  positions_ = storage(context_, positions);
  // (also the G-buffer's index buffer)
  indices_ = vk::upload_buffer(context_, indices.data(), indices.size() * sizeof(uint32_t),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
  normals_ = storage(context_, normals);
}

void GpuScene::upload_materials() {
  // Each image once, however many slots sample it.
  std::vector<uint32_t> texels, first_texel;
  for (const Texture& texture : scene_.textures) {
    first_texel.push_back(uint32_t(texels.size()));
    texels.insert(texels.end(), texture.texels.begin(), texture.texels.end());
  }
  std::vector<gpu::GpuMaterial> materials;
  material_ranges_.clear();
  instance_colors_.clear();
  for (const Instance& instance : scene_.instances) {
    // One slot without an image is one colour: drawn without looking materials up.
    const bool one_color = instance.materials.empty() ||
                           (instance.materials.size() == 1 && instance.materials[0].texture < 0);
    instance_colors_.push_back(instance.materials.empty() ? instance.base_color : instance.materials[0].base_color);
    material_ranges_.emplace_back(uint32_t(materials.size()), one_color ? 0u : uint32_t(instance.materials.size()));
    if (one_color) continue;
    for (const Material& material : instance.materials) {
      gpu::GpuMaterial m{};
      m.base_color = glm::vec4(material.base_color, 1.0f);
      if (material.texture >= 0) {
        const Texture& texture = scene_.textures[size_t(material.texture)];
        m.texel_first = first_texel[size_t(material.texture)];
        m.width = uint32_t(texture.width);
        m.height = uint32_t(texture.height);
      }
      materials.push_back(m);
    }
  }
  // (a storage buffer is never empty)
  if (materials.empty()) materials.emplace_back();
  if (texels.empty()) texels.push_back(0u);
  materials_ = storage(context_, materials);
  texels_ = storage(context_, texels);
}

void GpuScene::build_bottom_level(uint32_t mesh) {
  mesh_bvhs_[mesh] = build_mesh_bvh(scene_.meshes[mesh]);
  pieces_[mesh] = mesh_pieces(scene_.meshes[mesh]);
}

void GpuScene::upload_bottom_levels() {
  std::vector<gpu::BvhNode> nodes;
  std::vector<gpu::WindingDipole> dipoles;
  std::vector<glm::vec4> corners;
  blas_roots_.clear();
  for (uint32_t m = 0; m < scene_.meshes.size(); ++m) {
    const Mesh& mesh = scene_.meshes[m];
    const Bvh& bvh = mesh_bvhs_[m];
    const uint32_t node_offset = uint32_t(nodes.size()), triangle_offset = uint32_t(corners.size() / 3);
    blas_roots_.push_back(node_offset);
    const std::vector<gpu::BvhNode> mesh_nodes = gpu_nodes(bvh, node_offset, triangle_offset);
    nodes.insert(nodes.end(), mesh_nodes.begin(), mesh_nodes.end());
    const std::vector<gpu::WindingDipole> mesh_dipoles = winding_dipoles(bvh, mesh, pieces_[m]);
    dipoles.insert(dipoles.end(), mesh_dipoles.begin(), mesh_dipoles.end());
    // The first corner's w is the thickness of the triangle's piece (0: a
    // sheet), the second's -1 where the triangle faces into its piece, see mesh_topology.h.
    for (uint32_t t : bvh.order)
      for (int k = 0; k < 3; ++k)
        corners.emplace_back(mesh.positions[mesh.indices[3 * t + k]],
                             k == 0 ? pieces_[m].thickness[t] : k == 1 && pieces_[m].faces_in[t] ? -1.0f : 1.0f);
  }
  rays_.bottom_nodes = storage(context_, nodes);
  rays_.triangles = storage(context_, corners);
  rays_.winding_dipoles = storage(context_, dipoles);
  mesh_tops_.clear();  // (their roots may have moved)
}

void GpuScene::build_top_level() {
  if (casters_.empty()) return;  // nothing to trace; ray_structures() refuses
  std::vector<Aabb> boxes;
  for (uint32_t i : casters_) {
    const Instance& instance = scene_.instances[i];
    Aabb box;
    const BvhBuildNode& root = mesh_bvhs_[instance.mesh].nodes[0];
    for (int corner = 0; corner < 8; ++corner) {
      glm::vec3 p(corner & 1 ? root.box.hi.x : root.box.lo.x, corner & 2 ? root.box.hi.y : root.box.lo.y,
                  corner & 4 ? root.box.hi.z : root.box.lo.z);
      box.grow(glm::vec3(instance.object_to_world * glm::vec4(p, 1.0f)));
    }
    boxes.push_back(box);
  }
  Bvh top = build_bvh(boxes, 1);
  std::vector<gpu::RayInstance> instances;
  for (uint32_t i : top.order) {
    const Instance& instance = scene_.instances[casters_[i]];
    gpu::RayInstance ray{};
    ray.world_to_object = glm::inverse(instance.object_to_world);
    ray.object_to_world = instance.object_to_world;
    ray.blas_root = blas_roots_[instance.mesh];
    ray.mirrored = glm::determinant(glm::mat3(instance.object_to_world)) < 0.0f ? 1u : 0u;
    instances.push_back(ray);
  }
  rays_.top_nodes = storage(context_, gpu_nodes(top));
  rays_.instances = storage(context_, instances);
}

void GpuScene::set_transforms(const std::vector<glm::mat4>& object_to_world) {
  if (object_to_world.size() != scene_.instances.size())
    throw Error("set_transforms: expected " + std::to_string(scene_.instances.size()) + " transforms");
  // Check only what changed: the matrices, before any is applied.
  for (const glm::mat4& m : object_to_world)
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(m[c][r])) throw Error("set_transforms: a transform has NaN or infinite entries");
  for (uint32_t i = 0; i < object_to_world.size(); ++i) {
    if (scene_.instances[i].object_to_world == object_to_world[i]) continue;
    mark_changed(i);  // where it was
    scene_.instances[i].object_to_world = object_to_world[i];
    mark_changed(i);  // and where it is now
  }
  update_bounds();
  if (!has_ray_structures_) return;
  Clock::time_point start = Clock::now();
  build_top_level();
  bvh_build_ms_ = ms_since(start);
}

void GpuScene::set_mesh_positions(uint32_t mesh, const std::vector<glm::vec3>& positions) {
  if (mesh >= scene_.meshes.size() || positions.size() != scene_.meshes[mesh].positions.size())
    throw Error("set_mesh_positions: the vertex count must stay the same");
  Mesh geometry = scene_.meshes[mesh];
  geometry.positions = positions;
  set_mesh(mesh, std::move(geometry));
}

void GpuScene::set_mesh(uint32_t mesh, Mesh geometry) {
  if (mesh >= scene_.meshes.size()) throw Error("set_mesh: there is no mesh " + std::to_string(mesh));
  Mesh& current = scene_.meshes[mesh];
  geometry.name = current.name;
  // Blender reports animated objects' geometry as updated on every frame
  // change, deformed or not: the same shape again is no deformation, and
  // keeps the mesh's field (new normals alone only reach the rasterizer).
  const bool shape_changed = geometry.positions != current.positions || geometry.indices != current.indices;
  if (!shape_changed && geometry.normals == current.normals) return;
  Scene::validate_mesh(geometry);
  if (!shape_changed) {
    current = std::move(geometry);
    upload_raster();
    return;
  }
  for (uint32_t i = 0; i < scene_.instances.size(); ++i)
    if (scene_.instances[i].mesh == mesh) mark_changed(i);  // the old shape
  // In place, checked as a whole through the extents (no copy of the scene
  // every frame a mesh deforms), and put back if the scene would be unusable.
  Mesh previous = std::exchange(current, std::move(geometry));
  MeshExtent previous_extent = std::exchange(extents_[mesh], MeshExtent(current));
  try {
    std::vector<uint32_t> all(scene_.instances.size());
    for (uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    scene_.validate_extent(scene_.world_bounds(all, extents_));
  } catch (const Error&) {
    current = std::move(previous);
    extents_[mesh] = std::move(previous_extent);
    throw;
  }
  mesh_versions_[mesh]++;
  for (uint32_t i = 0; i < scene_.instances.size(); ++i)
    if (scene_.instances[i].mesh == mesh) mark_changed(i);  // the new one
  update_bounds();
  upload_raster();
  if (!has_ray_structures_) return;
  Clock::time_point start = Clock::now();
  build_bottom_level(mesh);
  upload_bottom_levels();
  build_top_level();
  bvh_build_ms_ = ms_since(start);
}

}  // namespace rtsdf
