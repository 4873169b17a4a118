#include "gpu_scene.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <utility>

#include "error.h"
#include "mesh_topology.h"
#include "winding_number.h"
#include "shaders/shared.h"
#include "vk/context.h"

namespace rtsdf {

namespace {

using Clock = std::chrono::steady_clock;

// A deformed mesh's refitted tree is kept while it costs at most this much
// more to trace than when it was built (bvh_cost); beyond, it is built anew.
constexpr float kRefitCostLimit = 1.5f;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

template <typename T>
vk::Buffer storage(const vk::Context& context, const std::vector<T>& data) {
  return vk::upload_buffer(context, data.data(), data.size() * sizeof(T), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
}

// The farthest any vertex moved from `before` to `after` (the same triangles).
double largest_move(const std::vector<glm::vec3>& before, const std::vector<glm::vec3>& after) {
  float largest = 0.0f;
  for (size_t i = 0; i < before.size(); ++i) largest = std::max(largest, glm::length(after[i] - before[i]));
  return double(largest);
}

uint64_t next_scene_id() {
  static std::atomic<uint64_t> next{1};
  return next++;
}

}  // namespace

void BoxesApart::grow(uint32_t instance, const Bounds& box) {
  if (many) return;
  auto own = std::find_if(boxes.begin(), boxes.end(), [instance](const auto& entry) { return entry.first == instance; });
  if (own != boxes.end()) {
    own->second = {glm::min(own->second.lo, box.lo), glm::max(own->second.hi, box.hi)};
  } else if (boxes.size() < gpu::kMaxShadowMovers) {
    boxes.emplace_back(instance, box);
  } else {
    boxes.clear();
    many = true;
  }
}

GpuScene::GpuScene(const vk::Context& context, const Scene& scene)
    : context_(context), id_(next_scene_id()), scene_(scene) {
  scene_.validate();
  extents_ = rtsdf::mesh_extents(scene_);
  mesh_versions_.assign(scene_.meshes.size(), 0);
  mesh_travel_.assign(scene_.meshes.size(), 0.0);
  mesh_triangles_versions_.assign(scene_.meshes.size(), 0);
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
  const Bounds b = scene_.world_bounds({instance}, extents_);
  if (b.is_empty()) return;  // an empty mesh
  auto grow = [&b](bool& any, Bounds& region) {
    region = any ? Bounds{glm::min(region.lo, b.lo), glm::max(region.hi, b.hi)} : b;
    any = true;
  };
  grow(changes_.any_moved, changes_.moved);
  changes_.instances.grow(instance, b);
  if (!std::binary_search(casters_.begin(), casters_.end(), instance)) return;
  grow(changes_.any, changes_.region);
  changes_.casters.grow(instance, b);
}

GpuScene::Changes GpuScene::take_changes() {
  Changes taken = changes_;
  changes_ = Changes{false, false, Bounds{}, false, Bounds{}, {}, {}};
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
    bottom_levels_.resize(scene_.meshes.size());
    for (uint32_t m = 0; m < scene_.meshes.size(); ++m) build_bottom_level(m);
    upload_bottom_levels();
    build_top_level();
    bvh_build_ms_ = ms_since(start);
    has_ray_structures_ = true;
  }
  return rays_;
}

const Bvh& GpuScene::mesh_bvh(uint32_t mesh) {
  ray_structures();
  if (mesh >= scene_.meshes.size()) throw Error("mesh_bvh: no mesh " + std::to_string(mesh));
  return bottom_levels_[mesh].bvh;
}

GpuScene::RayTargets GpuScene::mesh_rays(uint32_t mesh) {
  const RayStructures& rays = ray_structures();
  if (mesh >= scene_.meshes.size()) throw Error("mesh_rays: no mesh " + std::to_string(mesh));
  mesh_tops_.resize(scene_.meshes.size());
  MeshTop& top = mesh_tops_[mesh];
  if (!top.top_nodes) {
    gpu::BvhNode root = gpu_nodes(bottom_levels_[mesh].bvh)[0];
    root.first = 0;
    root.count = 1;  // a leaf over the one instance
    gpu::RayInstance instance{};
    instance.world_to_object = instance.object_to_world = glm::mat4(1.0f);
    instance.blas_root = blas_roots_[mesh];
    instance.first_triangle = first_triangles_[mesh];
    instance.triangle_count = uint32_t(bottom_levels_[mesh].corners.size() / 3);
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

namespace {

// One mesh's vertices as the G-buffer draws them. A vertex shared by faces of
// several material slots becomes one per slot (the G-buffer takes the slot
// from the vertex, not the triangle: a fragment shader that reads its
// primitive's index is 8x slower on lavapipe).
struct RasterMesh {
  std::vector<glm::vec3> positions, normals, colors;
  std::vector<glm::vec2> uvs;
  std::vector<uint32_t> slots, indices;  // indices from the mesh's first vertex
};

RasterMesh raster_mesh(const Mesh& mesh) {
  RasterMesh out;
  out.indices = mesh.indices;
  std::vector<uint32_t> vertex_source(mesh.positions.size());
  for (uint32_t v = 0; v < vertex_source.size(); ++v) vertex_source[v] = v;
  out.slots.assign(mesh.positions.size(), 0u);
  if (!mesh.materials.empty()) {
    std::unordered_map<uint64_t, uint32_t> split;
    std::vector<uint8_t> taken(mesh.positions.size(), 0);
    for (size_t c = 0; c < out.indices.size(); ++c) {
      const uint32_t v = mesh.indices[c], slot = mesh.materials[c / 3];
      if (!taken[v]) {
        taken[v] = 1;
        out.slots[v] = slot;
        split[(uint64_t(v) << 32) | slot] = v;
        continue;
      }
      auto [it, added] = split.try_emplace((uint64_t(v) << 32) | slot, uint32_t(vertex_source.size()));
      if (added) {
        vertex_source.push_back(v);
        out.slots.push_back(slot);
      }
      out.indices[c] = it->second;
    }
  }
  for (uint32_t source : vertex_source) {
    out.positions.push_back(mesh.positions[source]);
    out.normals.push_back(mesh.normals.empty() ? glm::vec3(0.0f) : mesh.normals[source]);
    out.uvs.push_back(mesh.uvs.empty() ? glm::vec2(0.0f) : mesh.uvs[source]);
    out.colors.push_back(mesh.colors.empty() ? glm::vec3(1.0f) : mesh.colors[source]);
  }
  return out;
}

}  // namespace

void GpuScene::upload_raster() {
  RasterMesh all;
  meshes_.clear();
  for (const Mesh& mesh : scene_.meshes) {
    RasterMesh one = raster_mesh(mesh);
    meshes_.push_back({uint32_t(all.indices.size()), uint32_t(all.positions.size()), uint32_t(mesh.triangle_count()),
                       uint32_t(one.positions.size())});
    all.positions.insert(all.positions.end(), one.positions.begin(), one.positions.end());
    all.normals.insert(all.normals.end(), one.normals.begin(), one.normals.end());
    all.uvs.insert(all.uvs.end(), one.uvs.begin(), one.uvs.end());
    all.colors.insert(all.colors.end(), one.colors.begin(), one.colors.end());
    all.slots.insert(all.slots.end(), one.slots.begin(), one.slots.end());
    all.indices.insert(all.indices.end(), one.indices.begin(), one.indices.end());
  }
  uvs_ = storage(context_, all.uvs);
  vertex_materials_ = storage(context_, all.slots);
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "positions are uploaded as packed floats");
  // (a source too: a deformation copies the vertices drawn before it)
  positions_ = vk::upload_buffer(context_, all.positions.data(), all.positions.size() * sizeof(glm::vec3),
                                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
  previous_positions_ = {};
  deformed_since_.assign(scene_.meshes.size(), 0);
  // (also the G-buffer's index buffer)
  indices_ = vk::upload_buffer(context_, all.indices.data(), all.indices.size() * sizeof(uint32_t),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
  normals_ = storage(context_, all.normals);
  colors_ = storage(context_, all.colors);
}

bool GpuScene::write_raster_in_place(uint32_t mesh, bool deformed) {
  GpuMeshRange& range = meshes_[mesh];
  RasterMesh one = raster_mesh(scene_.meshes[mesh]);
  if (one.positions.size() != range.vertex_count || one.indices.size() != 3 * size_t(range.triangle_count))
    return false;
  if (deformed && !deformed_since_[mesh] && range.vertex_count > 0) {
    // The first deformation since the interval began: the vertices drawn before it.
    if (!previous_positions_)
      previous_positions_ = vk::Buffer(context_, positions_.size(), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                       vk::Buffer::Access::DeviceOnly);
    context_.submit_and_wait([&](VkCommandBuffer cmd) {
      const VkDeviceSize first = VkDeviceSize(range.base_vertex) * sizeof(glm::vec3);
      const VkBufferCopy region{first, first, VkDeviceSize(range.vertex_count) * sizeof(glm::vec3)};
      vkCmdCopyBuffer(cmd, positions_.handle(), previous_positions_.handle(), 1, &region);
    });
    deformed_since_[mesh] = 1;
  }
  vk::BufferWrites writes;
  writes.add_range(positions_, range.base_vertex, one.positions);
  writes.add_range(normals_, range.base_vertex, one.normals);
  writes.add_range(uvs_, range.base_vertex, one.uvs);
  writes.add_range(colors_, range.base_vertex, one.colors);
  writes.add_range(vertex_materials_, range.base_vertex, one.slots);
  writes.add_range(indices_, range.first_index, one.indices);
  writes.submit(context_);
  return true;
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
    const bool one_color = instance.materials.empty() || (instance.materials.size() == 1 &&
                                                          instance.materials[0].texture < 0 &&
                                                          !instance.materials[0].vertex_color);
    instance_colors_.push_back(instance.materials.empty() ? instance.base_color : instance.materials[0].base_color);
    material_ranges_.emplace_back(uint32_t(materials.size()), one_color ? 0u : uint32_t(instance.materials.size()));
    if (one_color) continue;
    for (const Material& material : instance.materials) {
      gpu::GpuMaterial m{};
      m.base_color = glm::vec4(material.base_color, 1.0f);
      m.vertex_color = material.vertex_color ? 1u : 0u;
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

void GpuScene::build_bottom_level(uint32_t mesh, bool same_triangles) {
  const Mesh& geometry = scene_.meshes[mesh];
  BottomLevel& level = bottom_levels_[mesh];
  bool refitted = same_triangles && level.built_cost > 0.0f;  // (0: never built)
  if (refitted) {
    refit_mesh_bvh(level.bvh, geometry);
    refitted = bvh_cost(level.bvh) <= kRefitCostLimit * level.built_cost;
  }
  if (!refitted) {
    level.bvh = build_mesh_bvh(geometry);
    level.built_cost = bvh_cost(level.bvh);
  }
  if (!same_triangles || level.topology.piece.size() != geometry.triangle_count())
    level.topology = piece_topology(geometry);
  level.pieces = mesh_pieces(geometry, level.topology);
  level.dipoles = winding_dipoles(level.bvh, geometry, level.pieces);
  // The first corner's w is the thickness of the triangle's piece (0: a
  // sheet), the second's -1 where the triangle faces into its piece, see mesh_topology.h.
  level.corners.clear();
  level.corners.reserve(3 * geometry.triangle_count());
  for (uint32_t t : level.bvh.order)
    for (int k = 0; k < 3; ++k)
      level.corners.emplace_back(geometry.positions[geometry.indices[3 * t + k]],
                                 k == 0 ? level.pieces.thickness[t] : k == 1 && level.pieces.faces_in[t] ? -1.0f : 1.0f);
}

void GpuScene::upload_bottom_levels() {
  std::vector<gpu::BvhNode> nodes;
  std::vector<gpu::WindingDipole> dipoles;
  std::vector<glm::vec4> corners;
  blas_roots_.clear();
  first_triangles_.clear();
  node_capacities_.clear();
  for (uint32_t m = 0; m < bottom_levels_.size(); ++m) {
    const BottomLevel& level = bottom_levels_[m];
    const uint32_t node_offset = uint32_t(nodes.size()), triangle_offset = uint32_t(corners.size() / 3);
    blas_roots_.push_back(node_offset);
    first_triangles_.push_back(triangle_offset);
    const std::vector<gpu::BvhNode> mesh_nodes = gpu_nodes(level.bvh, node_offset, triangle_offset);
    nodes.insert(nodes.end(), mesh_nodes.begin(), mesh_nodes.end());
    dipoles.insert(dipoles.end(), level.dipoles.begin(), level.dipoles.end());
    corners.insert(corners.end(), level.corners.begin(), level.corners.end());
    // A mesh that has deformed will again: its range holds the most nodes a
    // tree over its triangles can have (2n - 1), so that each rebuilt tree is
    // written where it is and the other meshes' levels are not uploaded again.
    const size_t capacity = mesh_versions_[m] > 0 ? std::max<size_t>(2 * level.corners.size() / 3, 1) - 1 : 0;
    node_capacities_.push_back(std::max(capacity, mesh_nodes.size()));
    nodes.resize(node_offset + node_capacities_.back());
    dipoles.resize(node_offset + node_capacities_.back());
  }
  rays_.bottom_nodes = storage(context_, nodes);
  rays_.triangles = storage(context_, corners);
  rays_.winding_dipoles = storage(context_, dipoles);
  mesh_tops_.clear();  // (their roots may have moved)
}

bool GpuScene::write_bottom_level_in_place(uint32_t mesh) {
  const BottomLevel& level = bottom_levels_[mesh];
  if (level.bvh.nodes.size() > node_capacities_[mesh]) return false;
  // (the caller has checked that the triangle count is the same)
  const uint32_t first_triangle = first_triangles_[mesh];
  const uint32_t root = blas_roots_[mesh];
  vk::BufferWrites writes;
  writes.add_range(rays_.bottom_nodes, root, gpu_nodes(level.bvh, root, first_triangle));
  writes.add_range(rays_.winding_dipoles, root, level.dipoles);
  writes.add_range(rays_.triangles, 3 * size_t(first_triangle), level.corners);
  writes.submit(context_);
  if (mesh < mesh_tops_.size()) mesh_tops_[mesh] = MeshTop{};  // (its root node's box changed)
  return true;
}

void GpuScene::build_top_level() {
  if (casters_.empty()) return;  // nothing to trace; ray_structures() refuses
  std::vector<Aabb> boxes;
  for (uint32_t i : casters_) {
    const Instance& instance = scene_.instances[i];
    Aabb box;
    const BvhBuildNode& root = bottom_levels_[instance.mesh].bvh.nodes[0];
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
    ray.first_triangle = first_triangles_[instance.mesh];
    ray.triangle_count = uint32_t(bottom_levels_[instance.mesh].corners.size() / 3);
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

double GpuScene::mesh_move_since(uint32_t mesh, uint64_t version, double travel, double& moved) const {
  const double now = mesh_travel_.at(mesh);
  moved = mesh_triangles_versions_[mesh] > version || version > mesh_versions_[mesh] ? std::numeric_limits<double>::infinity()
                                                                                     : now - travel;
  return now;
}

std::vector<uint8_t> GpuScene::take_deformations() {
  std::vector<uint8_t> taken(scene_.meshes.size(), 0);
  std::swap(taken, deformed_since_);
  return taken;
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
    if (!write_raster_in_place(mesh, false)) upload_raster();
    return;
  }
  for (uint32_t i = 0; i < scene_.instances.size(); ++i)
    if (scene_.instances[i].mesh == mesh) mark_changed(i);  // the old shape
  // In place, checked as a whole through the extents (no copy of the scene
  // every frame a mesh deforms), and put back if the scene would be unusable.
  Mesh previous = std::exchange(current, std::move(geometry));
  const bool same_triangles = current.indices == previous.indices;
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
  if (same_triangles)
    mesh_travel_[mesh] += largest_move(previous.positions, current.positions);
  else
    mesh_triangles_versions_[mesh] = mesh_versions_[mesh];
  for (uint32_t i = 0; i < scene_.instances.size(); ++i)
    if (scene_.instances[i].mesh == mesh) mark_changed(i);  // the new one
  update_bounds();
  // A deformation keeps the counts: only this mesh's ranges are rewritten.
  const bool in_place = write_raster_in_place(mesh, true);
  if (!in_place) upload_raster();
  if (!has_ray_structures_) return;
  Clock::time_point start = Clock::now();
  build_bottom_level(mesh, same_triangles);
  if (!in_place || !write_bottom_level_in_place(mesh)) upload_bottom_levels();
  build_top_level();
  bvh_build_ms_ = ms_since(start);
}

}  // namespace rtsdf
