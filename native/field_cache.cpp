#include "field_cache.h"

#include <cstdio>
#include <cstring>
#include <type_traits>

#include "field_store.h"
#include "packed_field.h"

namespace rtsdf {

uint64_t digest_bytes(const void* data, size_t size, uint64_t hash) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) hash = (hash ^ bytes[i]) * 0x100000001b3ull;
  return hash;
}

std::string FieldKey::describe() const {
  std::string text;
  auto add = [&text](auto value) {
    char item[40];
    if constexpr (std::is_floating_point_v<decltype(value)>)
      std::snprintf(item, sizeof item, "%a ", double(value));  // (hexadecimal: every bit)
    else
      std::snprintf(item, sizeof item, "%llu ", static_cast<unsigned long long>(value));
    text += item;
  };
  std::apply([&add](const auto&... member) { (add(member), ...); }, members());
  text.pop_back();
  return text;
}

uint64_t topology_digest(size_t vertex_count, const std::vector<uint32_t>& indices) {
  const uint64_t counts[2] = {vertex_count, indices.size()};
  const uint64_t hash = digest_bytes(counts, sizeof(counts));
  return digest_bytes(indices.data(), indices.size() * sizeof(uint32_t), hash);
}

uint64_t topology_digest(const Mesh& mesh) { return topology_digest(mesh.positions.size(), mesh.indices); }

uint64_t geometry_digest(const Mesh& mesh, uint64_t topology) {
  return digest_bytes(mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3), topology);
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
  std::shared_ptr<FieldStore> store;
  {
    std::lock_guard lock(mutex_);
    keep(key, field);
    store = store_;
  }
  if (store) store->save(key, field);
}

void FieldCache::keep(const FieldKey& key, const CachedField& field) {
  const size_t bytes = field.packed->bytes();
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

void FieldCache::set_store(std::shared_ptr<FieldStore> store) {
  std::lock_guard lock(mutex_);
  store_ = std::move(store);
}

std::shared_ptr<FieldStore> FieldCache::store() const {
  std::lock_guard lock(mutex_);
  return store_;
}

std::optional<CachedField> FieldCache::load(const FieldKey& key, const vk::Context& context,
                                            std::shared_ptr<const FieldPackPass> pass) {
  const std::shared_ptr<FieldStore> from = store();
  if (!from) return std::nullopt;
  std::optional<CachedField> field = from->load(key, context, std::move(pass));
  if (field) {
    std::lock_guard lock(mutex_);
    keep(key, *field);
  }
  return field;
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
