#include "field_store.h"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <fstream>
#include <iterator>
#include <type_traits>
#include <vector>

#include "error.h"
#include "packed_field.h"

namespace rtsdf {

namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'R', 'T', 'S', 'D', 'F', 'f', 'l', 'd'};
constexpr uint32_t kFormat = 1;
constexpr const char* kExtension = ".rtsdf-field";

// What a file holds before its key's text and its words (plain data, read
// and written whole, by the same build on the same machine's byte order).
struct FileHeader {
  char magic[8];
  uint32_t format;
  uint32_t key_length;    // bytes of the key's text that follow the header
  uint64_t build;
  uint64_t word_count;    // words that follow the key's text
  uint64_t digest;        // of the key's text and the words: a torn or corrupt file reads as none
  GridSpec coarse_grid, fine_grid;  // CachedField's
  GridSpec grid, far_grid;          // PackedField::Saved's
  float box_lo[3], box_hi[3], margin;
  uint32_t capacity, stored;
};
static_assert(std::is_trivially_copyable_v<GridSpec>);

uint64_t content_digest(const std::string& key_text, const std::vector<uint32_t>& words) {
  const uint64_t hash = digest_bytes(key_text.data(), key_text.size());
  return digest_bytes(words.data(), words.size() * sizeof(uint32_t), hash);
}

std::string hex(uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

}  // namespace

uint64_t FieldStore::build_identity() {
  static const uint64_t identity = [] {
    Dl_info info{};
    std::string path = "/proc/self/exe";
    if (dladdr(reinterpret_cast<void*>(&FieldStore::build_identity), &info) != 0 && info.dli_fname &&
        *info.dli_fname)
      path = info.dli_fname;
    std::ifstream file(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    if (bytes.empty()) throw Error("FieldStore: cannot read this build's binary (" + path + ") to tell builds apart");
    return digest_bytes(bytes.data(), bytes.size());
  }();
  return identity;
}

FieldStore::FieldStore(fs::path directory, size_t capacity_bytes, uint64_t build)
    : directory_(std::move(directory)), capacity_(capacity_bytes), build_(build) {
  std::error_code error;
  fs::create_directories(directory_, error);
  if (error || !fs::is_directory(directory_))
    throw Error("cannot use " + directory_.string() + " to keep fields on disk: " +
                (error ? error.message() : std::string("not a directory")));
}

fs::path FieldStore::path_of(const std::string& key_text) const {
  return directory_ / (hex(digest_bytes(key_text.data(), key_text.size(), build_)) + kExtension);
}

std::optional<CachedField> FieldStore::load(const FieldKey& key, const vk::Context& context,
                                            std::shared_ptr<const FieldPackPass> pass) {
  const std::string key_text = key.describe();
  const fs::path path = path_of(key_text);
  std::ifstream file(path, std::ios::binary);
  if (!file) return std::nullopt;
  // A file that is not this key's whole field is removed (its key's next
  // save writes it anew); one that could not be laid out on the device is
  // left for a later try.
  auto pass_over = [this, &file, &path](bool remove = true) {
    file.close();
    std::error_code ignored;
    if (remove) fs::remove(path, ignored);
    std::lock_guard lock(mutex_);
    stats_.passed_over++;
    return std::nullopt;
  };
  FileHeader header{};
  std::error_code size_error;
  const uintmax_t file_bytes = fs::file_size(path, size_error);
  // (the words' count checked against the file's size before anything is allocated for them)
  if (!file.read(reinterpret_cast<char*>(&header), sizeof header) ||
      std::memcmp(header.magic, kMagic, sizeof kMagic) != 0 || header.format != kFormat || header.build != build_ ||
      header.key_length != key_text.size() || header.word_count > (uint64_t(1) << 32) || size_error ||
      file_bytes != sizeof header + header.key_length + header.word_count * sizeof(uint32_t))
    return pass_over();
  std::string text(header.key_length, '\0');
  PackedField::Saved saved{header.grid, header.far_grid, glm::vec3(header.box_lo[0], header.box_lo[1], header.box_lo[2]),
                           glm::vec3(header.box_hi[0], header.box_hi[1], header.box_hi[2]), header.margin,
                           header.capacity, header.stored, std::vector<uint32_t>(header.word_count)};
  if (!file.read(text.data(), std::streamsize(text.size())) || text != key_text ||
      !file.read(reinterpret_cast<char*>(saved.words.data()), std::streamsize(saved.words.size() * sizeof(uint32_t))) ||
      content_digest(text, saved.words) != header.digest)
    return pass_over();
  CachedField field;
  try {
    field.packed = PackedField::load(context, std::move(pass), saved);
  } catch (const Error&) {  // (out of device memory, say)
    return pass_over(false);
  }
  field.coarse_grid = header.coarse_grid;
  field.fine_grid = header.fine_grid;
  std::error_code ignored;  // (the file's time orders eviction: it was used now)
  fs::last_write_time(path, fs::file_time_type::clock::now(), ignored);
  std::lock_guard lock(mutex_);
  stats_.loaded++;
  return field;
}

void FieldStore::save(const FieldKey& key, const CachedField& field) {
  const std::string key_text = key.describe();
  const fs::path path = path_of(key_text);
  std::error_code error;
  if (fs::exists(path, error)) return;
  const PackedField::Saved saved = field.packed->save();
  FileHeader header{};
  std::memcpy(header.magic, kMagic, sizeof kMagic);
  header.format = kFormat;
  header.key_length = uint32_t(key_text.size());
  header.build = build_;
  header.word_count = saved.words.size();
  header.digest = content_digest(key_text, saved.words);
  header.coarse_grid = field.coarse_grid;
  header.fine_grid = field.fine_grid;
  header.grid = saved.grid;
  header.far_grid = saved.far_grid;
  for (int axis = 0; axis < 3; ++axis) {
    header.box_lo[axis] = saved.box_lo[axis];
    header.box_hi[axis] = saved.box_hi[axis];
  }
  header.margin = saved.margin;
  header.capacity = saved.capacity;
  header.stored = saved.stored;

  // Written whole under a name of its own, then renamed: another process
  // reading the store sees the whole file or none.
  static std::atomic<uint64_t> serial{0};
  const fs::path partial = path.string() + ".partial." + std::to_string(getpid()) + "." + std::to_string(serial++);
  bool written = false;
  {
    std::ofstream file(partial, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(&header), sizeof header);
    file.write(key_text.data(), std::streamsize(key_text.size()));
    file.write(reinterpret_cast<const char*>(saved.words.data()), std::streamsize(saved.words.size() * sizeof(uint32_t)));
    file.close();
    written = bool(file);
  }
  if (written) fs::rename(partial, path, error);
  std::lock_guard lock(mutex_);
  if (!written || error) {
    fs::remove(partial, error);
    stats_.failed_saves++;
    stats_.last_error = "cannot write " + path.string() + (written ? ": " + error.message() : std::string(""));
    return;
  }
  stats_.saved++;
  evict_to_capacity();
}

std::vector<FieldStore::File> FieldStore::files() const {
  std::vector<File> found;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory_, error)) {
    if (entry.path().extension() != kExtension) continue;
    std::error_code ignored;  // (a file another process removed meanwhile counts as empty)
    found.push_back({entry.last_write_time(ignored), size_t(entry.file_size(ignored)), entry.path()});
  }
  return found;
}

void FieldStore::evict_to_capacity() {
  std::vector<File> kept = files();
  size_t total = 0;
  for (const File& file : kept) total += file.bytes;
  if (total <= capacity_) return;
  std::sort(kept.begin(), kept.end(), [](const File& a, const File& b) { return a.time < b.time; });
  for (const File& file : kept) {
    if (total <= capacity_) break;
    std::error_code ignored;
    if (fs::remove(file.path, ignored)) total -= file.bytes;
  }
}

FieldStore::Stats FieldStore::stats() const {
  std::lock_guard lock(mutex_);
  Stats stats = stats_;
  for (const File& file : files()) {
    stats.files++;
    stats.bytes += file.bytes;
  }
  return stats;
}

}  // namespace rtsdf
