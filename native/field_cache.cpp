#include "field_cache.h"

#include <cstring>

#include "packed_field.h"

namespace rtsdf {

namespace {

// FNV-1a over raw bytes: the same floats give the same digest, and any changed bit another.
uint64_t fnv1a(const void* data, size_t size, uint64_t hash) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) hash = (hash ^ bytes[i]) * 0x100000001b3ull;
  return hash;
}

}  // namespace

bool FieldKey::operator==(const FieldKey& other) const {
  return geometry == other.geometry && coarse_resolution == other.coarse_resolution &&
         fine_resolution == other.fine_resolution && beta == other.beta && updates == other.updates &&
         fine.trace_band == other.fine.trace_band && fine.decay == other.fine.decay &&
         fine.rays_per_texel == other.fine.rays_per_texel && fine.interleave == other.fine.interleave &&
         fine.trace_everywhere == other.fine.trace_everywhere && fine.skip_converged == other.fine.skip_converged;
}

uint64_t topology_digest(size_t vertex_count, const std::vector<uint32_t>& indices) {
  const uint64_t counts[2] = {vertex_count, indices.size()};
  const uint64_t hash = fnv1a(counts, sizeof(counts), 0xcbf29ce484222325ull);
  return fnv1a(indices.data(), indices.size() * sizeof(uint32_t), hash);
}

uint64_t topology_digest(const Mesh& mesh) { return topology_digest(mesh.positions.size(), mesh.indices); }

uint64_t geometry_digest(const Mesh& mesh, uint64_t topology) {
  return fnv1a(mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3), topology);
}

FieldCache::FieldCache(size_t capacity_bytes) : capacity_(capacity_bytes) {}

std::optional<CachedField> FieldCache::find(const FieldKey& key) {
  std::lock_guard lock(mutex_);
  for (auto it = entries_.begin(); it != entries_.end(); ++it)
    if (it->key == key) {
      entries_.splice(entries_.begin(), entries_, it);
      return it->field;
    }
  return std::nullopt;
}

void FieldCache::insert(const FieldKey& key, const CachedField& field) {
  const size_t bytes = field.packed->bytes();
  std::lock_guard lock(mutex_);
  for (auto it = entries_.begin(); it != entries_.end(); ++it)
    if (it->key == key) {
      bytes_ -= it->bytes;
      entries_.erase(it);
      break;
    }
  if (bytes > capacity_) return;
  evict_to(capacity_ - bytes);
  entries_.push_front({key, field, bytes});
  bytes_ += bytes;
}

void FieldCache::evict_to(size_t bytes) {
  while (bytes_ > bytes && !entries_.empty()) {
    bytes_ -= entries_.back().bytes;
    entries_.pop_back();
  }
}

std::optional<float> FieldCache::feature_size(uint64_t geometry) const {
  std::lock_guard lock(mutex_);
  auto it = feature_sizes_.find(geometry);
  return it == feature_sizes_.end() ? std::nullopt : std::optional<float>(it->second);
}

void FieldCache::remember_feature_size(uint64_t geometry, float size) {
  std::lock_guard lock(mutex_);
  feature_sizes_[geometry] = size;
}

void FieldCache::clear() {
  std::lock_guard lock(mutex_);
  entries_.clear();
  feature_sizes_.clear();
  bytes_ = 0;
}

size_t FieldCache::bytes() const {
  std::lock_guard lock(mutex_);
  return bytes_;
}

size_t FieldCache::size() const {
  std::lock_guard lock(mutex_);
  return entries_.size();
}

}  // namespace rtsdf
