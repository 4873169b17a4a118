#pragma once
// Refined fields of meshes that do not deform, kept between the renderers of
// one device (the viewport, F12 renders, each frame of an animation render):
// a mesh whose geometry and field settings match a field already refined
// takes that field and traces nothing. A rigid mesh's field depends on its
// own geometry only, so a new render of a scene whose objects only moved,
// or of the same scene again, builds no field at all.
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <unordered_map>

#include "grid.h"
#include "passes/fine_trace.h"
#include "scene.h"

namespace rtsdf {

class FieldPackPass;
class PackedField;

// What a mesh's field is made from: its geometry (a digest of its positions
// and triangles) and every setting the build and refinement read.
struct FieldKey {
  uint64_t geometry = 0;
  int coarse_resolution = 0, fine_resolution = 0;
  float beta = 0.0f;
  FineTraceSettings fine;
  int updates = 0;  // fine updates it had

  // Every member above, for comparing and for describing (one list for both).
  auto members() const {
    return std::tie(geometry, coarse_resolution, fine_resolution, beta, updates, fine.trace_band, fine.decay,
                    fine.rays_per_texel, fine.interleave, fine.trace_everywhere, fine.skip_converged);
  }
  bool operator==(const FieldKey& other) const { return members() == other.members(); }
  // The members as text, floats to the bit (a FieldStore file names its key with it).
  std::string describe() const;
};

// FNV-1a over raw bytes: the same bytes give the same digest, and any changed bit another.
uint64_t digest_bytes(const void* data, size_t size, uint64_t seed = 0xcbf29ce484222325ull);

// A digest of a mesh's triangles alone (their vertex indices, and how many
// vertices): meshes that share it may be copies whose vertices differ by
// rounding (near_copy).
uint64_t topology_digest(const Mesh& mesh);
// ... of `vertex_count` vertices joined by `indices` (three per triangle).
uint64_t topology_digest(size_t vertex_count, const std::vector<uint32_t>& indices);
// A digest of its positions and triangles, from its topology_digest (its
// name and normals do not shape its field).
uint64_t geometry_digest(const Mesh& mesh, uint64_t topology);

struct CachedField {
  std::shared_ptr<PackedField> packed;  // read-only once cached: its holders only read it
  GridSpec coarse_grid, fine_grid;
};

class FieldStore;

class FieldCache {
 public:
  // Keeps at most `capacity_bytes` of fields; the least recently used go first.
  explicit FieldCache(size_t capacity_bytes);

  std::optional<CachedField> find(const FieldKey& key);
  // A refined field; not kept when larger than the capacity. Saved in the
  // store too, when there is one.
  void insert(const FieldKey& key, const CachedField& field);

  // Fields kept on disk between processes (null: none), consulted where
  // find() misses: a field refined once is never traced again, as Unreal
  // keeps its meshes' distance fields in its derived data cache.
  void set_store(std::shared_ptr<FieldStore> store);
  std::shared_ptr<FieldStore> store() const;
  // The field from the store, kept here too; none without a store or a file.
  std::optional<CachedField> load(const FieldKey& key, const vk::Context& context,
                                  std::shared_ptr<const FieldPackPass> pass);
  // A geometry's feature size (mesh_detail.h), by its digest: its probe
  // builds the mesh's BVH, which a renderer that takes every field from here
  // and casts no exact ray would build for nothing (the 2CylinderEngine's
  // Preview render: 140 ms of 650). A few bytes a geometry; kept until clear().
  std::optional<float> feature_size(uint64_t geometry) const;
  void remember_feature_size(uint64_t geometry, float size);
  void clear();

  size_t bytes() const;
  size_t size() const;
  size_t capacity() const { return capacity_; }

 private:
  struct Entry {
    FieldKey key;
    CachedField field;
    size_t bytes = 0;
  };
  void evict_to(size_t bytes);  // (with the lock held)

  // (with the lock held) the field as the most recently used
  void keep(const FieldKey& key, const CachedField& field);

  mutable std::mutex mutex_;  // a viewport and an F12 render may run on two threads
  std::shared_ptr<FieldStore> store_;
  const size_t capacity_;
  size_t bytes_ = 0;
  std::list<Entry> entries_;  // most recently used first
  std::unordered_map<uint64_t, float> feature_sizes_;  // geometry digest -> feature size
};

}  // namespace rtsdf
