#pragma once
// Refined fields kept on disk, so that a mesh's field is traced once and
// never again in a later process: the next F12 of a saved scene, each
// frame of a command-line animation render, a viewport opened on the same
// scene tomorrow. As Unreal keeps its meshes' distance fields in its
// derived data cache, built once per mesh, not at render time.
//
// A file holds one packed field (PackedField::Saved) and its grids, named
// by a digest of its FieldKey and of the build that made it: a field is
// only ever read by the code that wrote it, since any change to the
// pipeline changes what a field holds. The directory keeps at most a given
// size of files; the least recently used go first.
//
// Nothing here fails a render: a file that cannot be read (another build's,
// torn, corrupt) is passed over and replaced; a file that cannot be written
// (a full disk, no permission) is counted and its reason kept.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "field_cache.h"

namespace rtsdf {

class FieldStore {
 public:
  // Makes `directory` if missing (Error where it cannot be made). `build`:
  // what tells builds apart (build_identity(); tests give others).
  FieldStore(std::filesystem::path directory, size_t capacity_bytes, uint64_t build = build_identity());

  std::optional<CachedField> load(const FieldKey& key, const vk::Context& context,
                                  std::shared_ptr<const FieldPackPass> pass);
  // Writes the field unless a file of its key is there already.
  void save(const FieldKey& key, const CachedField& field);

  struct Stats {
    int loaded = 0, saved = 0;
    int passed_over = 0;   // files found but not read: torn, corrupt, or not this key's
    int failed_saves = 0;  // (the last one's reason in last_error)
    std::string last_error;
    size_t files = 0, bytes = 0;  // in the directory now
  };
  Stats stats() const;
  const std::filesystem::path& directory() const { return directory_; }
  size_t capacity() const { return capacity_; }

  // A digest of the binary this code is in (the Python module, a test):
  // another build, another digest.
  static uint64_t build_identity();

 private:
  std::filesystem::path path_of(const std::string& key_text) const;  // (FieldKey::describe's)
  struct File {
    std::filesystem::file_time_type time;  // last written or read (load renews it)
    size_t bytes;
    std::filesystem::path path;
  };
  std::vector<File> files() const;  // the fields in the directory now
  void evict_to_capacity();  // (with the lock held)

  const std::filesystem::path directory_;
  const size_t capacity_;
  const uint64_t build_;
  mutable std::mutex mutex_;
  Stats stats_;
};

}  // namespace rtsdf
