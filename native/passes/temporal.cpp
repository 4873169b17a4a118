#include "passes/temporal.h"

#include <utility>

#include "error.h"
#include "spirv/spirv_temporal_keep_comp.h"
#include "spirv/spirv_temporal_quad_groups_comp.h"
#include "spirv/spirv_temporal_resolve_comp.h"

namespace rtsdf {

namespace {
constexpr VkDescriptorType kImage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
constexpr VkDescriptorType kBuffer = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
constexpr VkDescriptorType kUniform = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
// Both passes' (temporal_keep.comp declares fewer of them: the surface's normal and albedo are the resolve's).
const std::vector<VkDescriptorType> kBindings = {kImage, kImage,   kImage,  kImage, kImage, kImage, kUniform, kBuffer,
                                                 kImage, kImage,   kBuffer, kImage, kImage, kImage, kImage};
}  // namespace

TemporalPass::TemporalPass(const vk::Context& context)
    : context_(context),
      keep_(context, RTSDF_SPIRV(spirv_temporal_keep_comp), kBindings, uint32_t(sizeof(gpu::TemporalPush))),
      quad_groups_(context, RTSDF_SPIRV(spirv_temporal_quad_groups_comp), {kBuffer}, uint32_t(sizeof(gpu::TemporalPush))),
      resolve_(context, RTSDF_SPIRV(spirv_temporal_resolve_comp), kBindings, uint32_t(sizeof(gpu::TemporalPush)),
               {0u}),
      resolve_listed_(context, RTSDF_SPIRV(spirv_temporal_resolve_comp), kBindings,
                      uint32_t(sizeof(gpu::TemporalPush)), {1u}) {}

namespace {
// The two lists' tiles (shaders/kept_tiles.glsl.h): pixel tiles, quad groups.
size_t tile_count(glm::ivec2 size, int tile) {
  const glm::ivec2 tiles = (size + tile - 1) / tile;
  return size_t(tiles.x) * size_t(tiles.y);
}
size_t pixel_tiles(glm::ivec2 size) { return tile_count(size, int(gpu::kTemporalTile)); }
size_t quad_groups(glm::ivec2 size) { return tile_count((size + 1) / 2, int(gpu::kQuadGroup)); }
// Each list's first word: its indirect dispatch, then a flag and a slot per tile.
VkDeviceSize quad_list_first(glm::ivec2 size) { return 4 + 2 * pixel_tiles(size); }
}  // namespace

KeptTiles TemporalPass::kept_tiles() const {
  return {tiles_, 0, quad_list_first(size_) * sizeof(uint32_t)};
}

void TemporalPass::resize(glm::ivec2 size) {
  if (size == size_ && tiles_) return;
  tiles_ = vk::Buffer(context_, (8 + 2 * pixel_tiles(size) + 2 * quad_groups(size)) * sizeof(uint32_t),
                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                          VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                      vk::Buffer::Access::DeviceOnly);
  size_ = size;
}

namespace {
// The bindings of both passes: the G-buffer's position and motion, this
// frame's sample, history, the frame, the lights, the resolved
// accumulation, the tile lists, the G-buffer's normal and albedo, and the
// second moments of history and of the resolved accumulation.
std::vector<vk::Resource> bindings(const GBufferPass& gbuffer, const TemporalImages& images, const vk::Buffer& frame,
                                   const vk::Buffer& lights, const vk::Buffer& tiles) {
  return {vk::Resource::storage_image(gbuffer.position()),      vk::Resource::storage_image(gbuffer.motion()),
          vk::Resource::storage_image(images.sample_color),     vk::Resource::storage_image(images.sample_passes),
          vk::Resource::storage_image(images.history_color),    vk::Resource::storage_image(images.history_passes),
          vk::Resource::uniform_buffer(frame),                  vk::Resource::storage_buffer(lights),
          vk::Resource::storage_image(images.resolved_color),   vk::Resource::storage_image(images.resolved_passes),
          vk::Resource::storage_buffer(tiles),                  vk::Resource::storage_image(gbuffer.normal()),
          vk::Resource::storage_image(gbuffer.albedo()),        vk::Resource::storage_image(images.history_moments),
          vk::Resource::storage_image(images.resolved_moments)};
}
}  // namespace

void TemporalPass::record_keep(VkCommandBuffer cmd, const GBufferPass& gbuffer, const TemporalImages& images,
                               const vk::Buffer& frame, const vk::Buffer& lights,
                               const gpu::TemporalPush& push) const {
  if (push.image_size != size_) throw Error("TemporalPass: resize to the image first");
  // (no tile listed yet, and dispatches of none)
  for (const auto& [first, count] :
       {std::pair{VkDeviceSize(0), pixel_tiles(size_)}, std::pair{quad_list_first(size_), quad_groups(size_)}}) {
    vk::clear_indirect_dispatch(cmd, tiles_, first * sizeof(uint32_t));
    vkCmdFillBuffer(cmd, tiles_.handle(), (first + 4) * sizeof(uint32_t), count * sizeof(uint32_t), 0u);
  }
  vk::memory_barrier(cmd, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  keep_.bind(cmd);
  keep_.push_descriptors(cmd, bindings(gbuffer, images, frame, lights, tiles_));
  keep_.push_constants(cmd, push);
  vkCmdDispatch(cmd, vk::group_count(size_.x, int(gpu::kTemporalTile)), vk::group_count(size_.y, int(gpu::kTemporalTile)), 1);
  vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  quad_groups_.bind(cmd);
  quad_groups_.push_descriptors(cmd, {vk::Resource::storage_buffer(tiles_)});
  quad_groups_.push_constants(cmd, push);
  vkCmdDispatch(cmd, vk::group_count(int(quad_groups(size_)), 64), 1, 1);
}

void TemporalPass::record(VkCommandBuffer cmd, const GBufferPass& gbuffer, const TemporalImages& images,
                          const vk::Buffer& frame, const vk::Buffer& lights, const gpu::TemporalPush& push,
                          bool after_keep) const {
  if (push.image_size != size_) throw Error("TemporalPass: resize to the image first");
  const vk::Pipeline& resolve = after_keep ? resolve_listed_ : resolve_;
  resolve.bind(cmd);
  resolve.push_descriptors(cmd, bindings(gbuffer, images, frame, lights, tiles_));
  resolve.push_constants(cmd, push);
  if (after_keep) {
    vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_INDIRECT_COMMAND_READ_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT);
    vkCmdDispatchIndirect(cmd, tiles_.handle(), 0);
  } else {
    vkCmdDispatch(cmd, vk::group_count(size_.x, int(gpu::kTemporalTile)), vk::group_count(size_.y, int(gpu::kTemporalTile)), 1);
  }
}

}  // namespace rtsdf
