#include "packed_field.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/gtc/packing.hpp>

#include "error.h"
#include "vk/context.h"

namespace rtsdf {

namespace {

// Texel `index` of half floats packed two to a word.
float half_texel(const uint32_t* words, size_t index) {
  const glm::vec2 pair = glm::unpackHalf2x16(words[index / 2]);
  return index % 2 == 0 ? pair.x : pair.y;
}

// Trilinear sample of the far field's texels (rows of `row` texels) at q, in
// their voxel space, clamped at the faces: as shaders/sdf_fields.glsl.h reads it.
float far_trilinear(const uint32_t* words, glm::ivec3 dims, int row, glm::vec3 q) {
  const glm::vec3 s = q - 0.5f;
  const glm::vec3 base = glm::floor(s);
  const glm::vec3 w = glm::clamp(s - base, 0.0f, 1.0f);
  const glm::ivec3 i0 = glm::clamp(glm::ivec3(base), glm::ivec3(0), dims - 1);
  const glm::ivec3 i1 = glm::clamp(glm::ivec3(base) + 1, glm::ivec3(0), dims - 1);
  auto at = [&](int x, int y, int z) { return half_texel(words, size_t(x) + size_t(row) * (size_t(y) + size_t(dims.y) * z)); };
  auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
  const float c00 = lerp(at(i0.x, i0.y, i0.z), at(i1.x, i0.y, i0.z), w.x);
  const float c10 = lerp(at(i0.x, i1.y, i0.z), at(i1.x, i1.y, i0.z), w.x);
  const float c01 = lerp(at(i0.x, i0.y, i1.z), at(i1.x, i0.y, i1.z), w.x);
  const float c11 = lerp(at(i0.x, i1.y, i1.z), at(i1.x, i1.y, i1.z), w.x);
  return lerp(lerp(c00, c10, w.y), lerp(c01, c11, w.y), w.z);
}

}  // namespace

PackedField::PackedField(const vk::Context& context, std::shared_ptr<const FieldPackPass> pass)
    : context_(context),
      pass_(pass ? std::move(pass) : std::make_shared<const FieldPackPass>(context)),
      count_(context, sizeof(uint32_t), VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::Buffer::Access::HostVisible) {
  std::memset(count_.mapped(), 0, sizeof(uint32_t));
}

void PackedField::set_layout(const GridSpec& grid, const GridSpec& far_grid, const Bounds& content, float room) {
  if (grid.origin != far_grid.origin || far_grid.voxel_size < grid.voxel_size)
    throw Error("PackedField: the far grid must share the grid's origin and have voxels at least as large");
  const glm::vec3 dims(grid.dims);
  const glm::vec3 content_lo = (content.lo - grid.origin) / grid.voxel_size;
  const glm::vec3 content_hi = (content.hi - grid.origin) / grid.voxel_size;
  box_lo_ = room < 0.0f ? glm::vec3(0.0f) : glm::clamp(content_lo - room, glm::vec3(0.0f), dims);
  box_hi_ = room < 0.0f ? dims : glm::clamp(content_hi + room, glm::vec3(0.0f), dims);
  const glm::vec3 margin = glm::min(content_lo - box_lo_, box_hi_ - content_hi);
  margin_ = std::max(0.0f, std::min(margin.x, std::min(margin.y, margin.z)));

  const bool same = words_ && grid.dims == grid_.dims && far_grid.dims == far_grid_.dims;
  if (same) {
    grid_ = grid;
    far_grid_ = far_grid;
    return;
  }
  lay_out_grids(grid, far_grid);
  stored_bricks_ = vk::Buffer(context_, (4 + size_t(brick_count())) * sizeof(uint32_t),
                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                                  VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                              vk::Buffer::Access::DeviceOnly);
  // No room for bricks yet: the first pack counts them, then makes room.
  stored_ = 0;
  allocate(0);
}

void PackedField::lay_out_grids(const GridSpec& grid, const GridSpec& far_grid) {
  grid_ = grid;
  far_grid_ = far_grid;
  bricks_ = bricks_of(grid.dims);
  far_row_ = far_grid.dims.x + far_grid.dims.x % 2;
  far_first_ = gpu::kBrickTableFirst + brick_count();
  bricks_first_ = far_first_ + uint32_t(size_t(far_row_) * far_grid.dims.y * far_grid.dims.z / 2);
}

size_t PackedField::word_count(uint32_t capacity) const {
  // (and a word to spare: the march reads texels in pairs of words)
  return size_t(bricks_first_) + size_t(capacity) * gpu::kBrickWords + 1;
}

void PackedField::allocate(uint32_t capacity) {
  const size_t words = word_count(capacity);
  if (words > size_t(UINT32_MAX)) throw Error("a distance field holds more than 2^32 words: lower the resolution");
  const size_t bytes = words * sizeof(uint32_t);
  if (bytes > context_.device_local_heap_bytes() / 2)
    throw Error("a distance field needs " + std::to_string(bytes >> 20) + " MiB: lower the resolution");
  words_ = vk::Buffer(context_, bytes,
                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
                          VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                      vk::Buffer::Access::DeviceOnly);
  context_.submit_and_wait([&](VkCommandBuffer cmd) {
    vkCmdFillBuffer(cmd, words_.handle(), 0, VK_WHOLE_SIZE, 0u);
    vk::memory_barrier(cmd, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  });
  capacity_ = capacity;
  generation_++;
}

void PackedField::record_pack(VkCommandBuffer cmd, const Source& source) const {
  if (!words_ || !source.coarse) throw Error("PackedField: pack a laid-out field from its coarse SDF");
  if (source.coarse->dims() != far_grid_.dims || (source.fine && source.fine->dims() != grid_.dims))
    throw Error("PackedField: the SDFs packed do not match the field's layout");
  gpu::FieldPackPush push{};
  const VkDeviceAddress address = words_.device_address();
  push.store = glm::uvec4(uint32_t(address), uint32_t(address >> 32), far_first_, bricks_first_);
  push.dims = glm::ivec4(grid_.dims, int(capacity_));
  push.coarse_dims = glm::ivec4(far_grid_.dims, far_row_);
  push.fine_grid = glm::vec4(grid_.origin, grid_.voxel_size);
  push.coarse_grid = glm::vec4(far_grid_.origin, far_grid_.voxel_size);
  push.params = glm::vec4(source.band, source.far_offset, 0.0f, 0.0f);
  // The count starts at zero; without a fine SDF no brick is stored.
  vkCmdFillBuffer(cmd, words_.handle(), 0, sizeof(uint32_t), 0u);
  vk::clear_indirect_dispatch(cmd, stored_bricks_);
  if (!source.fine)
    vkCmdFillBuffer(cmd, words_.handle(), gpu::kBrickTableFirst * sizeof(uint32_t), brick_count() * sizeof(uint32_t),
                    gpu::kNoBrick);
  vk::memory_barrier(cmd, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  pass_->record(cmd, push, *source.coarse, source.fine, bricks_, stored_bricks_);
  VkBufferCopy count{0, 0, sizeof(uint32_t)};
  vkCmdCopyBuffer(cmd, words_.handle(), count_.handle(), 1, &count);
  vk::memory_barrier(cmd, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_PIPELINE_STAGE_HOST_BIT);
}

bool PackedField::settle(float slack) {
  uint32_t count = 0;
  std::memcpy(&count, count_.mapped(), sizeof count);
  stored_ = std::min(count, capacity_);
  if (count <= capacity_) return true;
  allocate(std::min(brick_count(), count + uint32_t(std::ceil(float(count) * std::max(slack, 0.0f)))));
  return false;
}

void PackedField::pack(const vk::Context& context, const std::vector<Packing>& packings) {
  std::vector<const Packing*> pending;
  for (const Packing& p : packings) pending.push_back(&p);
  for (int round = 0; !pending.empty(); ++round) {
    if (round == 2) throw Error("a packed field did not fit the room made for it");
    context.submit_and_wait([&](VkCommandBuffer cmd) {
      for (const Packing* p : pending) p->field->record_pack(cmd, p->source);
    });
    std::vector<const Packing*> again;
    for (const Packing* p : pending)
      if (!p->field->settle(p->slack)) again.push_back(p);
    pending = std::move(again);
  }
}

void PackedField::release() {
  words_ = {};
  stored_bricks_ = {};
  grid_ = far_grid_ = {};
  capacity_ = stored_ = 0;
  generation_++;
}

gpu::FieldInstance PackedField::instance_record() const {
  gpu::FieldInstance record{};
  const VkDeviceAddress address = words_.device_address();
  record.scale.z = margin_;
  record.store = glm::uvec4(uint32_t(address), uint32_t(address >> 32), far_first_, bricks_first_);
  record.dims = glm::ivec4(grid_.dims, int(capacity_));
  record.far_dims = glm::ivec4(far_grid_.dims, far_row_);
  record.box_lo = glm::vec4(box_lo_, grid_.voxel_size / far_grid_.voxel_size);
  record.box_hi = glm::vec4(box_hi_, 0.0f);
  return record;
}

std::vector<uint32_t> PackedField::read_words() const {
  if (!words_) return {};
  vk::Buffer readback(context_, words_.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::Buffer::Access::HostVisible);
  context_.submit_and_wait([&](VkCommandBuffer cmd) {
    VkBufferCopy all{0, 0, words_.size()};
    vkCmdCopyBuffer(cmd, words_.handle(), readback.handle(), 1, &all);
    vk::memory_barrier(cmd, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT);
  });
  const uint32_t* first = static_cast<const uint32_t*>(readback.mapped());
  return std::vector<uint32_t>(first, first + words_.size() / sizeof(uint32_t));
}

PackedField::Saved PackedField::save() const {
  if (!words_) throw Error("PackedField: only a laid-out, packed field can be saved");
  return {grid_, far_grid_, box_lo_, box_hi_, margin_, capacity_, stored_, read_words()};
}

std::shared_ptr<PackedField> PackedField::load(const vk::Context& context, std::shared_ptr<const FieldPackPass> pass,
                                               const Saved& saved) {
  auto field = std::make_shared<PackedField>(context, std::move(pass));
  const glm::ivec3 dims = saved.grid.dims, far_dims = saved.far_grid.dims;
  if (glm::any(glm::lessThan(dims, glm::ivec3(1))) || glm::any(glm::lessThan(far_dims, glm::ivec3(1))) ||
      glm::any(glm::greaterThan(dims, glm::ivec3(4096))) || glm::any(glm::greaterThan(far_dims, dims)))
    throw Error("PackedField: a saved field's grids are out of range");
  field->lay_out_grids(saved.grid, saved.far_grid);
  if (saved.stored > saved.capacity || saved.capacity > field->brick_count() ||
      saved.words.size() != field->word_count(saved.capacity))
    throw Error("PackedField: a saved field's words do not fit its layout");
  field->box_lo_ = saved.box_lo;
  field->box_hi_ = saved.box_hi;
  field->margin_ = saved.margin;
  field->stored_ = saved.stored;
  field->capacity_ = saved.capacity;
  field->words_ = vk::upload_buffer(context, saved.words.data(), saved.words.size() * sizeof(uint32_t),
                                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
                                        VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
  field->generation_++;
  return field;
}

std::vector<float> PackedField::read_texels() const {
  if (!words_) return {};
  const std::vector<uint32_t> all_words = read_words();
  const uint32_t* words = all_words.data();
  const float far_scale = grid_.voxel_size / far_grid_.voxel_size;
  std::vector<float> texels(grid_.voxel_count());
  for (int z = 0; z < grid_.dims.z; ++z)
    for (int y = 0; y < grid_.dims.y; ++y)
      for (int x = 0; x < grid_.dims.x; ++x) {
        const glm::ivec3 t(x, y, z);
        const glm::ivec3 brick = glm::min(t / int(gpu::kBrickCells), bricks_ - 1);
        const glm::ivec3 local = t - brick * int(gpu::kBrickCells);
        const uint32_t slot =
            words[gpu::kBrickTableFirst + brick.x + bricks_.x * (brick.y + size_t(bricks_.y) * brick.z)];
        const float voxels =
            slot < capacity_
                ? half_texel(words + bricks_first_ + size_t(slot) * gpu::kBrickWords, local.x + 8 * (local.y + 8 * local.z))
                : far_trilinear(words + far_first_, far_grid_.dims, far_row_, (glm::vec3(t) + 0.5f) * far_scale);
        texels[size_t(x) + size_t(grid_.dims.x) * (y + size_t(grid_.dims.y) * z)] = voxels * grid_.voxel_size;
      }
  return texels;
}

}  // namespace rtsdf
