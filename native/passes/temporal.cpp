#include "passes/temporal.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "error.h"
#include "spirv/spirv_temporal_converged_comp.h"
#include "spirv/spirv_temporal_keep_comp.h"
#include "spirv/spirv_temporal_quad_groups_comp.h"
#include "spirv/spirv_temporal_resolve_comp.h"

namespace rtsdf {

namespace {
constexpr VkDescriptorType kImage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
constexpr VkDescriptorType kBuffer = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
constexpr VkDescriptorType kUniform = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
// Both passes' (the resolve's and the keep pass's).
const std::vector<VkDescriptorType> kBindings = {kImage, kImage,  kImage, kImage, kImage, kImage, kUniform, kBuffer,
                                                 kImage, kImage,  kBuffer, kImage, kImage, kImage, kImage, kBuffer};
}  // namespace

TemporalPass::TemporalPass(const vk::Context& context)
    : context_(context),
      keep_(context, RTSDF_SPIRV(spirv_temporal_keep_comp), kBindings, uint32_t(sizeof(gpu::TemporalPush))),
      quad_groups_(context, RTSDF_SPIRV(spirv_temporal_quad_groups_comp), {kBuffer}, uint32_t(sizeof(gpu::TemporalPush))),
      resolve_(context, RTSDF_SPIRV(spirv_temporal_resolve_comp), kBindings, uint32_t(sizeof(gpu::TemporalPush)),
               {0u}),
      resolve_listed_(context, RTSDF_SPIRV(spirv_temporal_resolve_comp), kBindings,
                      uint32_t(sizeof(gpu::TemporalPush)), {1u}),
      converged_(context, RTSDF_SPIRV(spirv_temporal_converged_comp), {kImage, kImage, kImage, kBuffer, kBuffer},
                 uint32_t(sizeof(gpu::TemporalPush))) {}

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
                          VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                      vk::Buffer::Access::DeviceOnly);
  // (a tile index per work group, written as a pass is recorded)
  auto tile_indices = [&] {
    return vk::Buffer(context_, std::max<size_t>(pixel_tiles(size), 1) * sizeof(uint32_t),
                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::Buffer::Access::HostVisible);
  };
  keep_tiles_ = tile_indices();
  tested_tiles_ = tile_indices();
  unsettled_ = vk::Buffer(context_, (pixel_tiles(size) + 1) * sizeof(uint32_t),
                          VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::Buffer::Access::HostVisible);
  size_ = size;
}

TileMask TemporalPass::keep_region(const TileMask& unsettled) const {
  // The tiles holding unsettled pixels (shaded and resolved there) and the
  // neighbours the resolve reads, 2 pixels out: a tile each way.
  auto reach = [](int t) { return glm::ivec2(t - 1, t + 1); };
  return unsettled.spread(reach, reach);
}

PixelRect TemporalPass::drawn_region(const TileMask& unsettled) const {
  const int tile = int(gpu::kTemporalTile), group = 2 * int(gpu::kQuadGroup);  // (a quad group's pixels across)
  auto floor_div = [](int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); };
  // Around each tile holding unsettled pixels, on each axis: the quad
  // groups listed beside it (temporal_quad_groups.comp: group g shares
  // samples with pixels 16g - 1 to 16g + 16, and reads those), and the
  // resolve's neighbours 2 pixels out (3: the quads' sample pixels the pixel
  // passes read); in tiles.
  auto reach = [&](int t) {
    const int lo = t * tile, hi = lo + tile;
    const int first_group = floor_div(lo - 1, group), last_group = floor_div(hi, group);
    const int first = std::min(group * first_group - 1, lo - 3), last = std::max(group * last_group + group + 1, hi + 3);
    return glm::ivec2(floor_div(first, tile), floor_div(last - 1, tile));
  };
  return unsettled.spread(reach, reach).bounds();
}

namespace {
// The bindings of both passes: the G-buffer's position and motion, this
// frame's sample, history, the frame, the lights, the resolved
// accumulation, the tile lists, the G-buffer's normal and albedo, the
// second moments of history and of the resolved accumulation, and the
// tiles the keep pass runs over.
std::vector<vk::Resource> bindings(const GBufferPass& gbuffer, const TemporalImages& images, const vk::Buffer& frame,
                                   const vk::Buffer& lights, const vk::Buffer& tiles, const vk::Buffer& keep_tiles) {
  return {vk::Resource::storage_image(gbuffer.position()),      vk::Resource::storage_image(gbuffer.motion()),
          vk::Resource::storage_image(images.sample.color),     vk::Resource::storage_image(images.sample.passes),
          vk::Resource::storage_image(images.history.color),    vk::Resource::storage_image(images.history.passes),
          vk::Resource::uniform_buffer(frame),                  vk::Resource::storage_buffer(lights),
          vk::Resource::storage_image(images.resolved.color),   vk::Resource::storage_image(images.resolved.passes),
          vk::Resource::storage_buffer(tiles),                  vk::Resource::storage_image(gbuffer.normal()),
          vk::Resource::storage_image(gbuffer.albedo()),        vk::Resource::storage_image(images.history.moments),
          vk::Resource::storage_image(images.resolved.moments), vk::Resource::storage_buffer(keep_tiles)};
}

// Copies `from` to `to` over `rects`, each image taken from GENERAL to the
// copy's layouts and back (GENERAL is where every pass uses them).
void copy_rects(VkCommandBuffer cmd, const std::vector<std::pair<const vk::Image*, const vk::Image*>>& pairs,
                const std::vector<PixelRect>& rects) {
  std::vector<VkImageCopy> copies;
  for (const PixelRect& r : rects) {
    VkImageCopy copy{};
    copy.srcSubresource = copy.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.srcOffset = copy.dstOffset = {r.lo.x, r.lo.y, 0};
    copy.extent = {uint32_t(r.size().x), uint32_t(r.size().y), 1};
    copies.push_back(copy);
  }
  if (copies.empty()) return;
  std::vector<std::pair<const vk::Image*, VkImageLayout>> layouts;  // (each image once: one is copied twice)
  for (const auto& [source, target] : pairs)
    for (const auto& entry : {std::pair{source, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL},
                              std::pair{target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL}})
      if (std::find(layouts.begin(), layouts.end(), entry) == layouts.end()) layouts.push_back(entry);
  for (const auto& [image, layout] : layouts)
    vk::image_barrier(cmd, image->handle(), VK_IMAGE_LAYOUT_GENERAL, layout, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                      VK_PIPELINE_STAGE_TRANSFER_BIT);
  for (const auto& [source, target] : pairs)
    vkCmdCopyImage(cmd, source->handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target->handle(),
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, uint32_t(copies.size()), copies.data());
  for (const auto& [image, layout] : layouts)
    vk::image_barrier(cmd, image->handle(), layout, VK_IMAGE_LAYOUT_GENERAL, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
}
}  // namespace

double TemporalPass::short_history_share() const {
  uint32_t count = 0;
  std::memcpy(&count, static_cast<const uint32_t*>(unsettled_.mapped()) + pixel_tiles(size_), sizeof count);
  return double(count) / double(size_.x * size_.y);
}

TileMask TemporalPass::unsettled_tiles() const {
  TileMask tiles(size_);
  std::vector<uint32_t> listed(pixel_tiles(size_));
  std::memcpy(listed.data(), unsettled_.mapped(), listed.size() * sizeof(uint32_t));
  for (size_t i = 0; i < listed.size(); ++i)
    if (listed[i]) tiles.mark({int(i % size_t(tiles.tiles().x)), int(i / size_t(tiles.tiles().x))});
  return tiles;
}

void TemporalPass::record_keep(VkCommandBuffer cmd, const GBufferPass& gbuffer, const TemporalImages& images,
                               const vk::Buffer& frame, const vk::Buffer& lights, gpu::TemporalPush push,
                               const TileMask& region) const {
  if (push.image_size != size_) throw Error("TemporalPass: resize to the image first");
  if (region.image_size() != size_) throw Error("TemporalPass: the keep pass's tiles must be of this image");
  const std::vector<uint32_t> keep_tiles = region.indices();
  std::memcpy(keep_tiles_.mapped(), keep_tiles.data(), keep_tiles.size() * sizeof(uint32_t));
  clear_lists(cmd);
  // Outside the region every pixel is settled: history as it was is its
  // resolved accumulation and its sample (for the resolve's neighbourhoods).
  copy_rects(cmd,
             {{&images.history.color, &images.resolved.color},
              {&images.history.passes, &images.resolved.passes},
              {&images.history.moments, &images.resolved.moments},
              {&images.history.color, &images.sample.color}},
             region.outside());
  vk::memory_barrier(cmd, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  keep_.bind(cmd);
  keep_.push_descriptors(cmd, bindings(gbuffer, images, frame, lights, tiles_, keep_tiles_));
  keep_.push_constants(cmd, push);
  if (!keep_tiles.empty()) vkCmdDispatch(cmd, uint32_t(keep_tiles.size()), 1, 1);
  list_quad_groups(cmd, push, /*short_history_count=*/true);
}

void TemporalPass::record_converged(VkCommandBuffer cmd, const Accumulation& accumulation,
                                    const gpu::TemporalPush& push, const TileMask& region) const {
  if (push.image_size != size_) throw Error("TemporalPass: resize to the image first");
  if (region.image_size() != size_) throw Error("TemporalPass: the converged test's tiles must be of this image");
  const std::vector<uint32_t> tested = region.indices();
  std::memcpy(tested_tiles_.mapped(), tested.data(), tested.size() * sizeof(uint32_t));
  // (the lists this frame's shading ran over are cleared after it)
  vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT);
  clear_lists(cmd);
  vk::memory_barrier(cmd, VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                     VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  converged_.bind(cmd);
  converged_.push_descriptors(
      cmd, {vk::Resource::storage_image(accumulation.color), vk::Resource::storage_image(accumulation.passes),
            vk::Resource::storage_image(accumulation.moments), vk::Resource::storage_buffer(tiles_),
            vk::Resource::storage_buffer(tested_tiles_)});
  converged_.push_constants(cmd, push);
  if (!tested.empty()) vkCmdDispatch(cmd, uint32_t(tested.size()), 1, 1);
  list_quad_groups(cmd, push, /*short_history_count=*/false);
}

void TemporalPass::clear_lists(VkCommandBuffer cmd) const {
  // (no tile listed yet, and dispatches of none; no rectangle of them)
  for (const auto& [first, count] :
       {std::pair{VkDeviceSize(0), pixel_tiles(size_)}, std::pair{quad_list_first(size_), quad_groups(size_)}}) {
    vk::clear_indirect_dispatch(cmd, tiles_, first * sizeof(uint32_t));
    vkCmdFillBuffer(cmd, tiles_.handle(), (first + 4) * sizeof(uint32_t), count * sizeof(uint32_t), 0u);
  }
}

void TemporalPass::list_quad_groups(VkCommandBuffer cmd, const gpu::TemporalPush& push, bool short_history_count) const {
  vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  // (the pixel tiles' flags, for the host: the next frame's region)
  vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT);
  // (and the count of pixels the keep pass marked short of history, after them)
  const VkBufferCopy copies[2] = {{4 * sizeof(uint32_t), 0, pixel_tiles(size_) * sizeof(uint32_t)},
                                  {gpu::kShortHistoryCountWord * sizeof(uint32_t),
                                   pixel_tiles(size_) * sizeof(uint32_t), sizeof(uint32_t)}};
  vkCmdCopyBuffer(cmd, tiles_.handle(), unsettled_.handle(), short_history_count ? 2 : 1, copies);
  vk::memory_barrier(cmd, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_PIPELINE_STAGE_HOST_BIT);
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
  resolve.push_descriptors(cmd, bindings(gbuffer, images, frame, lights, tiles_, keep_tiles_));
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
