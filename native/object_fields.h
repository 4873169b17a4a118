#pragma once
// The object-space design (beyond the paper, which builds one field for the
// whole scene every frame): one field per unique mesh that casts shadows, in
// the mesh's own space, built with the paper's pipeline (coarse SDF by jump
// flooding, fine SDF ray traced in a band around the surfaces and accumulated
// over updates) and shared by every instance of the mesh.
// - A rigid motion moves instances and touches no field.
// - A mesh whose geometry changes (deformation) is rebuilt in its own grid,
//   keeping the fine SDF's history where the grid stays (the paper's
//   per-frame path, per mesh).
// - A field is refined in its first updates after a (re)build, then left
//   as it is: a still field costs nothing.
// - The march reads each field packed (PackedField): bricks near the
//   surfaces, the coarse SDF elsewhere. Once a field is refined its coarse
//   and fine SDFs are freed, unless the mesh deforms and its history is kept.
// - Meshes of one geometry (copies an importer or a duplicate made) share
//   the first one's field.
// - Each mesh's voxels come from its own size, under a memory budget.
// - A refined field of a mesh that does not deform goes into the device's
//   FieldCache (when given), and a later renderer's mesh of the same
//   geometry and settings takes it instead of building its own, as a
//   later process does from the cache's FieldStore (on disk) when it has one.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <tuple>
#include <vector>

#include "coarse_sdf.h"
#include "mesh_topology.h"
#include "field_cache.h"
#include "fine_sdf.h"
#include "march_fields.h"

namespace rtsdf {

struct ObjectFieldSettings {
  int coarse_resolution = 64;  // voxels on the longest axis of each mesh's coarse grid
  int fine_resolution = 128;   // voxels on the longest axis of each mesh's fine grid
  float beta = 0.5f;           // coarse voxels
  FineTraceSettings fine;
  // Fine updates of a field after each (re)build; 0: four passes over its
  // band (4 x fine.interleave updates).
  int updates = 4;
  // Keep a deformed mesh's grid (and so its fine SDF's history) while the
  // mesh stays inside it; the grid then has `grid_slack` x the mesh's
  // extent of room around it. Off: every rebuild starts afresh on a tight grid.
  bool keep_history = false;
  float grid_slack = 0.0f;
  // Device memory for all fields while they refine (coarse and fine SDFs,
  // and the packed fields), in MiB: resolutions are lowered alike until the
  // fields fit.
  double budget_mb = 1024.0;
  // The fields' surfaces together, in voxels (each field's surface area
  // over its fine voxel's face, summed): resolutions are lowered alike
  // until they fit. A field's trace works on the texels near its surface,
  // so its cost follows this. A model in many parts (a CAD assembly
  // imported as its parts) gives each part a field at its own size's
  // resolution, and together they held many times the surface voxels of
  // the model's field as one mesh (kSurfaceVoxelBudget).
  double surface_voxel_budget = 0.0;  // 0: kSurfaceVoxelBudget
};

// The default surface_voxel_budget. The 2CylinderEngine (assimp-testmodels'
// glTF, 110k triangles) imported as its 67 parts (29 meshes): 1.29 M surface
// voxels at the add-on's Fine 128, its F12 41.5 s of fine trace against 5.0
// s for the same model as one mesh (0.11 M), and 4.7x EEVEE's whole F12.
// The bundled samples hold 0.009 M (the character) to 0.29 M (large_small).
constexpr double kSurfaceVoxelBudget = 400000.0;

// One mesh's field, as the stats report it.
struct FieldMemory {
  uint32_t mesh = 0;
  size_t bytes = 0;            // packed, and its SDFs while kept
  uint32_t stored_bricks = 0;  // of brick_count
  uint32_t brick_count = 0;
  float voxel_size = 0.0f;     // of its fine grid, in the mesh's own units
  float detail = 1.0f;         // the factor its detail put on its resolutions (mesh_detail.h)
};

struct ObjectFieldStats {
  int fields = 0;               // fields held (one per geometry among the meshes)
  int placed = 0;               // instances placed (sharing those fields)
  int regenerated = 0;          // fields (re)built by the last sync
  int reused = 0;               // fields the last sync took refined from the FieldCache
  int loaded = 0;               // ... of which its FieldStore read from disk
  int refined = 0;              // fields updated by the last refine
  uint64_t traced_texels = 0;   // texels traced by the last refine
  size_t bytes = 0;             // device memory of the fields now: packed, and the SDFs of those not freed
  size_t peak_bytes = 0;        // the most they held since the last sync (while refining: what the budget bounds)
  size_t dense_bytes = 0;       // what dense grids of the same voxels take (coarse and fine SDFs and a dense copy)
  uint64_t stored_bricks = 0;   // bricks of fine texels the packed fields hold
  uint64_t brick_count = 0;     // bricks their fine grids span
  std::vector<FieldMemory> per_field;  // in mesh order
  float resolution_scale = 1;   // below 1: resolutions lowered to fit the budgets
  bool surface_limited = false;  // ... and the surface voxel budget was the one that lowered them
  int skipped_degenerate = 0;   // instances left out: a scale flattens them
};

// Rays per texel and frame where a deforming mesh's field keeps its history
// (a viewport's). FineSdfTest.ADeformingRealMeshIsFollowedWithFewRays, a
// 20k-triangle CAD part under a travelling wave of up to two fine voxels a
// frame, after 12 frames against OpenVDB (mean |error| in fine voxels,
// wrong signs), with texels keeping their own and their neighbours'
// nearest triangles and their last sign (fine_trace.comp): 1 ray 0.058,
// 0.05%; 2 rays 0.057, 0.12%; 4 rays 0.064, 0.12%; 8 rays 0.071, 0.12%.
// Before, when texels kept only a decaying value: 4 rays (then this
// setting) 0.343, 0.12%; 8 rays 0.320.
constexpr int kDeformingRaysPerTexel = 1;

class ObjectFields {
 public:
  // `cache` (may be null) is shared with the device's other renderers.
  explicit ObjectFields(const vk::Context& context, std::shared_ptr<FieldCache> cache = nullptr);

  // Brings the fields up to date with the scene's shadow casters and places
  // every caster instance in `march`: a mesh new to the fields, changed in
  // geometry or with other settings gets its coarse SDF (re)built and is
  // due for refinement. Throws rtsdf::Error when even the coarsest fields
  // exceed the budget.
  void sync(GpuScene& scene, const ObjectFieldSettings& settings, MarchFields& march);
  // One fine update of every field still due, copied into `march` (with any
  // field `march` lost in a new layout). Call after sync.
  void refine(GpuScene& scene, MarchFields& march);
  // Whether some field is still due for refinement.
  bool refining() const;
  // Frees every field (another method is in use).
  void clear() { fields_.clear(); placements_.clear(); }

  const ObjectFieldStats& stats() const { return stats_; }
  // A mesh's field as the march reads it (in its own space; for a mesh
  // that shares a copy's field, that one), or null if it has no field or
  // was never refined.
  const PackedField* packed_field(uint32_t mesh) const;
  // Per instance of the scene: the world size of its field's voxel (0: in no field).
  const std::vector<float>& instance_voxels() const { return instance_voxels_; }

 private:
  struct Field {
    uint32_t mesh = 0;
    uint64_t version = 0;
    int coarse_resolution = 0, fine_resolution = 0;
    float detail = 1.0f;  // the factor its detail put on them (mesh_detail.h)
    float beta = 0.0f;
    GridSpec coarse_grid, fine_grid;
    std::unique_ptr<CoarseSdf> coarse;
    std::unique_ptr<FineSdf> fine;
    std::shared_ptr<PackedField> packed;
    FieldKey key;                 // what it was built from
    bool borrowed = false;        // `packed` is in the FieldCache: read it, never pack or lay it out
    int updates = 0;              // since the last (re)build
    int quiet_updates = 0;        // the last updates in a row in which no texel improved
    bool unpacked = false;        // updated since its last packing
    bool deforms = false;         // rebuilt for a deformation since it was made
    uint64_t placed_generation = 0;  // its packed words' generation when placed
    uint64_t traced_version = 0;  // the mesh's version at its last update, and its travel then (GpuScene::mesh_move_since)
    double traced_travel = 0.0;
  };
  int update_limit() const;
  bool due(const Field& field) const { return field.updates < update_limit(); }
  void rebuild(GpuScene& scene, Field& field, const Bounds& bounds, int coarse_resolution, int fine_resolution);
  // Takes a refined field of the same geometry and settings from the cache, if it holds one.
  bool reuse(GpuScene& scene, Field& field, const FieldKey& key);
  // Packs the fields for the march, with more room for those that need it.
  void pack(const std::vector<Field*>& fields);
  void update_memory_stats();
  // A mesh's geometry_digest (and what copy_of compares), read again only when its geometry changed.
  uint64_t digest(const GpuScene& scene, uint32_t mesh);
  double surface_area(const GpuScene& scene, uint32_t mesh);
  // Copies are compared in one of two forms: the triangles as stored, or
  // welded (weld_by_position: an importer's split vertices need not come
  // alike in two copies of a part, turned, their normals rounded apart).
  enum class Form { Stored, Welded };
  uint64_t topology(const GpuScene& scene, uint32_t mesh, Form form);
  // Where mesh b lies as a near copy of mesh a (copy_placement, in that
  // form; a's bounds given), or none; remembered by their digests.
  std::optional<glm::mat4> copy_of(const GpuScene& scene, uint32_t a, const Bounds& bounds, uint32_t b, Form form);
  // The mesh's feature size, measured once per set of triangles (features_).
  float feature_size(GpuScene& scene, uint32_t mesh);
  struct Digest {
    uint64_t version = 0;  // the mesh's version it was taken from
    uint64_t digest = 0;
    uint64_t topology[2] = {};  // topology_digest, per Form
    float spread[2] = {};       // vertex_spread, per Form
    std::shared_ptr<const WeldedTriangles> weld;  // which vertices the welded form joins, and its triangles
    double area = 0.0;  // the mesh's surface area
  };

  const vk::Context& context_;
  std::shared_ptr<FieldCache> cache_;
  std::shared_ptr<CoarsePasses> coarse_passes_;
  std::shared_ptr<const FineTracePass> fine_pass_;
  std::shared_ptr<const FieldPackPass> pack_pass_;
  ObjectFieldSettings settings_;
  uint64_t scene_id_ = 0;
  std::vector<Field> fields_;  // by mesh index (of the first mesh of each geometry), in the march's layout order
  std::map<uint32_t, Digest> digests_;  // per caster mesh
  std::map<uint32_t, uint32_t> readers_;  // per caster mesh with a field: the mesh whose field it reads (its own or a copy's)
  std::map<std::tuple<uint64_t, uint64_t, Form>, std::optional<glm::mat4>> copies_;  // copy_of's verdicts, by the two digests
  // A mesh's feature size (mesh_detail.h), kept while its triangles are the
  // same ones: a deforming mesh keeps its first shape's, and so its grid.
  struct Feature {
    size_t triangles = 0;
    float size = 0.0f;
  };
  std::map<uint32_t, Feature> features_;  // per mesh with a field
  std::vector<MarchFields::Placement> placements_;
  std::vector<float> instance_voxels_;
  ObjectFieldStats stats_;
};

}  // namespace rtsdf
