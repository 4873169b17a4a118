#pragma once
// The scene on the device, in the two forms the passes read:
// - for rasterization: every mesh's positions and indices in shared buffers;
// - for ray tracing, built on first request (the coarse SDF never needs it):
//   one BVH per mesh (bottom level, object space) and a BVH over the
//   instances (top level, rebuilt whenever a transform changes).
#include <vector>

#include "bvh.h"
#include "mesh_extent.h"
#include "mesh_topology.h"
#include "scene.h"
#include "vk/resources.h"

namespace rtsdf {

struct GpuMeshRange {
  uint32_t first_index = 0;
  uint32_t base_vertex = 0;
  uint32_t triangle_count = 0;
  uint32_t vertex_count = 0;  // as uploaded (with the vertices split between material slots)
};

// The boxes of a few changed instances, each its own (instance, box: the
// union of its old and new bounds), while they are at most
// gpu::kMaxShadowMovers; beyond, none (`many`), and their union stands for
// them. Objects that move apart change little of the space between them.
struct BoxesApart {
  std::vector<std::pair<uint32_t, Bounds>> boxes;
  bool many = false;
  void grow(uint32_t instance, const Bounds& box);
};

class GpuScene {
 public:
  // Validates and uploads `scene`; throws rtsdf::Error on bad input.
  GpuScene(const vk::Context& context, const Scene& scene);

  // What a ray tracer binds (shaders/ray_trace.glsl.h): a top level over
  // placed meshes and the bottom levels it refers to.
  struct RayTargets {
    const vk::Buffer& top_nodes;
    const vk::Buffer& instances;
    const vk::Buffer& bottom_nodes;
    const vk::Buffer& triangles;
    const vk::Buffer& winding_dipoles;  // one per bottom-level node (winding_number.h)
  };
  struct RayStructures {
    vk::Buffer top_nodes;
    vk::Buffer instances;
    vk::Buffer bottom_nodes;
    vk::Buffer triangles;  // three corners per triangle, in bottom-level leaf order; w of the first: piece thickness, of the second: -1 where it faces into its piece
    vk::Buffer winding_dipoles;
    RayTargets targets() const { return {top_nodes, instances, bottom_nodes, triangles, winding_dipoles}; }
  };

  // A rigid motion: only the top level is rebuilt.
  void set_transforms(const std::vector<glm::mat4>& object_to_world);
  // A deforming mesh (same triangles, new positions): only its own BVH is rebuilt.
  void set_mesh_positions(uint32_t mesh, const std::vector<glm::vec3>& positions);
  // A mesh's new geometry in its place (its name kept): positions, triangles
  // and normals, in any number (a deformed quad may split along its other
  // diagonal). Only its own BVH is rebuilt; nothing at all for the same geometry.
  void set_mesh(uint32_t mesh, Mesh geometry);

  const vk::Buffer& positions() const { return positions_; }
  // The vertices of the meshes that deformed in place since the last
  // take_deformations(), as they were then, laid out as positions() (the
  // G-buffer's motion follows each vertex of a deforming mesh); positions()
  // itself until a mesh deforms.
  const vk::Buffer& previous_positions() const { return previous_positions_ ? previous_positions_ : positions_; }
  // Per mesh: whether previous_positions() holds its vertices from before a
  // deformation since the last call. Starts the next such interval.
  std::vector<uint8_t> take_deformations();
  const vk::Buffer& indices() const { return indices_; }
  // Per-vertex normals, (0,0,0) where a mesh has none (flat shading).
  const vk::Buffer& normals() const { return normals_; }
  // Per-vertex UVs ((0,0) where a mesh has none), and material slot (a
  // vertex shared by faces of several slots is uploaded once per slot).
  const vk::Buffer& uvs() const { return uvs_; }
  const vk::Buffer& vertex_materials() const { return vertex_materials_; }
  // Per-vertex colours, white where a mesh has none.
  const vk::Buffer& colors() const { return colors_; }
  // Every instance's material slots (gpu::GpuMaterial), and their images' texels.
  const vk::Buffer& materials() const { return materials_; }
  const vk::Buffer& texels() const { return texels_; }
  // An instance's slots in materials(): (first, count); count 0: one colour
  // everywhere, instance_color() (its base colour, or its one slot's colour).
  glm::uvec2 material_range(uint32_t instance) const { return material_ranges_.at(instance); }
  glm::vec3 instance_color(uint32_t instance) const { return instance_colors_.at(instance); }
  const std::vector<GpuMeshRange>& meshes() const { return meshes_; }
  const std::vector<Instance>& instances() const { return scene_.instances; }
  const Scene& scene() const { return scene_; }

  // Which instances go into the SDFs (the voxelization and the BVH): one flag
  // per instance, by default each instance's casts_shadow. A change rebuilds
  // only the top-level BVH.
  void set_shadow_casters(const std::vector<uint8_t>& casters);
  const std::vector<uint32_t>& shadow_casters() const { return casters_; }
  // World bounds of the shadow casters, which the SDF grids are fitted to
  // (zero-sized when there are none).
  const Bounds& bounds() const { return bounds_; }
  // Each mesh's extent (mesh_extent.h), current with set_mesh.
  const std::vector<MeshExtent>& mesh_extents() const { return extents_; }
  size_t triangle_count() const { return scene_.triangle_count(); }

  // What changed in the shadow casters since the last take_changes(): the
  // union of the old and new world bounds of the casters that moved or
  // deformed (`any`), or `everything` after the upload or a change of which
  // instances cast shadows. The fine SDF retraces only near such changes.
  // `moved`: the same union over every instance that moved or deformed,
  // casting shadows or not (`any_moved`), for what the camera saw move.
  // `casters` and `instances`: each one's own part of `region` and
  // `moved` (see BoxesApart).
  struct Changes {
    bool everything = true;
    bool any = false;
    Bounds region;
    bool any_moved = false;
    Bounds moved;
    BoxesApart casters, instances;
  };
  Changes take_changes();
  // The changes take_changes() would take now.
  const Changes& pending_changes() const { return changes_; }

  // The BVHs over the shadow casters, built (or brought up to date) on first
  // use. Throws rtsdf::Error when there is no shadow caster.
  const RayStructures& ray_structures();
  // One mesh alone in its own space (a top level of one untransformed
  // instance over its bottom level), for tracing its object-space field.
  // Builds the ray structures first if needed.
  RayTargets mesh_rays(uint32_t mesh);
  // One mesh's bottom level as built on the host (object space; see bvh.h).
  // Builds the ray structures first if needed.
  const Bvh& mesh_bvh(uint32_t mesh);
  // Object-space bounds of a mesh's vertices (empty for a mesh without any).
  Bounds mesh_bounds(uint32_t mesh) const;
  // Counts the shape changes of a mesh (set_mesh or set_mesh_positions with
  // other positions or triangles than it has), from 0.
  uint64_t mesh_version(uint32_t mesh) const { return mesh_versions_.at(mesh); }
  // The most any point of a mesh's surface moved since its version
  // `version` (mesh_version), and that move's `travel` (what this returned
  // then; 0 at version 0): the sum of each shape change's largest vertex move
  // (each point of a triangle is a blend of its corners, and moves by the
  // same blend of their moves); infinite where its triangles changed since.
  // Returns the travel now, for the next call.
  double mesh_move_since(uint32_t mesh, uint64_t version, double travel, double& moved) const;
  // Tells this scene from any other made in the process, even at the same address.
  uint64_t id() const { return id_; }
  // CPU milliseconds of the last BVH work (bottom levels built + top level); 0 before any.
  double bvh_build_ms() const { return bvh_build_ms_; }

 private:
  void upload_raster();
  // Rewrites one mesh's vertices and indices where they are, when it keeps
  // their counts (a deformation); false when its range would change size.
  // deformed: the vertices moved (previous_positions() keeps those drawn).
  bool write_raster_in_place(uint32_t mesh, bool deformed);
  void upload_materials();
  // same_triangles: the mesh deformed (its triangles as they were, moved):
  // its tree is refitted, unless that made it too costly to trace.
  void build_bottom_level(uint32_t mesh, bool same_triangles = false);
  void upload_bottom_levels();
  // Rewrites one mesh's bottom level where it is, when it keeps its triangle
  // count and its nodes fit its range; false otherwise.
  bool write_bottom_level_in_place(uint32_t mesh);
  void build_top_level();
  void update_bounds();
  void mark_changed(uint32_t instance);  // adds the instance's current world bounds, if it casts shadows

  struct MeshTop {
    vk::Buffer top_nodes;
    vk::Buffer instances;
  };

  const vk::Context& context_;
  uint64_t id_;
  Scene scene_;
  std::vector<uint64_t> mesh_versions_;
  std::vector<double> mesh_travel_;                // per mesh: the sum of its shape changes' largest vertex moves
  std::vector<uint64_t> mesh_triangles_versions_;  // ... and its version when its triangles last changed
  std::vector<MeshTop> mesh_tops_;  // for mesh_rays(), made on first use (empty buffers: not yet)
  std::vector<uint32_t> casters_;  // instance indices
  Bounds bounds_;
  std::vector<MeshExtent> extents_;  // one per mesh, for instance bounds
  Changes changes_;
  vk::Buffer positions_;
  vk::Buffer previous_positions_;       // (made on the first deformation in place)
  std::vector<uint8_t> deformed_since_;  // per mesh: previous_positions_ holds its vertices from before
  vk::Buffer indices_;
  vk::Buffer normals_;
  vk::Buffer uvs_;
  vk::Buffer vertex_materials_;
  vk::Buffer colors_;
  vk::Buffer materials_;
  vk::Buffer texels_;
  std::vector<glm::uvec2> material_ranges_;
  std::vector<glm::vec3> instance_colors_;
  std::vector<GpuMeshRange> meshes_;
  bool has_ray_structures_ = false;
  // One mesh's bottom level as built on the host: a deforming mesh rebuilds
  // its own, and the others' are copied, not derived again.
  struct BottomLevel {
    Bvh bvh;
    float built_cost = 0.0f;  // bvh_cost when the tree was built (its refits are held to it)
    PieceTopology topology;  // kept while its triangles stay the same (see mesh_topology.h)
    Pieces pieces;
    std::vector<gpu::WindingDipole> dipoles;
    std::vector<glm::vec4> corners;  // as in RayStructures::triangles
  };
  std::vector<BottomLevel> bottom_levels_;  // per mesh
  std::vector<uint32_t> blas_roots_;
  std::vector<uint32_t> first_triangles_;  // per mesh: where its triangles start in the triangle buffer
  std::vector<size_t> node_capacities_;  // per mesh: the nodes its range in bottom_nodes can hold
  RayStructures rays_;
  double bvh_build_ms_ = 0.0;
};

}  // namespace rtsdf
