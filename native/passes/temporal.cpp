#include "passes/temporal.h"

#include <algorithm>
#include <cstring>
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
  if (!unsettled_)
    unsettled_ = vk::Buffer(context_, 4 * sizeof(uint32_t),
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                            vk::Buffer::Access::HostVisible);
  size_ = size;
}

PixelRect TemporalPass::keep_region(const PixelRect& unsettled) const {
  if (unsettled.is_empty()) return {};
  const int tile = int(gpu::kTemporalTile), group = 2 * int(gpu::kQuadGroup);  // (a quad group's pixels across)
  auto floor_div = [](int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); };
  // The tiles holding the unsettled pixels (shaded and resolved there).
  const glm::ivec2 lo = unsettled.lo / tile * tile, hi = (unsettled.hi + tile - 1) / tile * tile;
  PixelRect region;
  for (int axis = 0; axis < 2; ++axis) {
    // The quad groups listed beside them (temporal_quad_groups.comp: group g
    // shares samples with pixels 16g - 1 to 16g + 16, and reads those), and
    // the resolve's neighbours 2 pixels out (3: the quads' sample pixels
    // the pixel passes read).
    const int first_group = floor_div(lo[axis] - 1, group), last_group = floor_div(hi[axis], group);
    region.lo[axis] = std::min(group * first_group - 1, lo[axis] - 3);
    region.hi[axis] = std::max(group * last_group + group + 1, hi[axis] + 3);
  }
  // Whole tiles (the keep pass's work groups), within the image.
  region.lo = glm::max(region.lo, glm::ivec2(0)) / tile * tile;
  region.hi = glm::min(region.hi, size_);
  return region;
}

namespace {
// The bindings of both passes: the G-buffer's position and motion, this
// frame's sample, history, the frame, the lights, the resolved
// accumulation, the tile lists, the G-buffer's normal and albedo, the
// second moments of history and of the resolved accumulation, and the keep
// pass's rectangle of the tiles it listed.
std::vector<vk::Resource> bindings(const GBufferPass& gbuffer, const TemporalImages& images, const vk::Buffer& frame,
                                   const vk::Buffer& lights, const vk::Buffer& tiles, const vk::Buffer& unsettled) {
  return {vk::Resource::storage_image(gbuffer.position()),      vk::Resource::storage_image(gbuffer.motion()),
          vk::Resource::storage_image(images.sample_color),     vk::Resource::storage_image(images.sample_passes),
          vk::Resource::storage_image(images.history_color),    vk::Resource::storage_image(images.history_passes),
          vk::Resource::uniform_buffer(frame),                  vk::Resource::storage_buffer(lights),
          vk::Resource::storage_image(images.resolved_color),   vk::Resource::storage_image(images.resolved_passes),
          vk::Resource::storage_buffer(tiles),                  vk::Resource::storage_image(gbuffer.normal()),
          vk::Resource::storage_image(gbuffer.albedo()),        vk::Resource::storage_image(images.history_moments),
          vk::Resource::storage_image(images.resolved_moments), vk::Resource::storage_buffer(unsettled)};
}

// The image outside `inside`, as up to four rectangles (the rows above and
// below it, the columns beside it).
std::vector<VkRect2D> outside(const PixelRect& inside, glm::ivec2 size) {
  auto rect = [](glm::ivec2 lo, glm::ivec2 hi) {
    return VkRect2D{{lo.x, lo.y}, {uint32_t(hi.x - lo.x), uint32_t(hi.y - lo.y)}};
  };
  if (inside.is_empty()) return {rect(glm::ivec2(0), size)};
  std::vector<VkRect2D> rects;
  if (inside.lo.y > 0) rects.push_back(rect({0, 0}, {size.x, inside.lo.y}));
  if (inside.hi.y < size.y) rects.push_back(rect({0, inside.hi.y}, size));
  if (inside.lo.x > 0) rects.push_back(rect({0, inside.lo.y}, {inside.lo.x, inside.hi.y}));
  if (inside.hi.x < size.x) rects.push_back(rect({inside.hi.x, inside.lo.y}, {size.x, inside.hi.y}));
  return rects;
}

// Copies `from` to `to` over `rects`, each image taken from GENERAL to the
// copy's layouts and back (GENERAL is where every pass uses them).
void copy_rects(VkCommandBuffer cmd, const std::vector<std::pair<const vk::Image*, const vk::Image*>>& pairs,
                const std::vector<VkRect2D>& rects) {
  std::vector<VkImageCopy> copies;
  for (const VkRect2D& r : rects) {
    VkImageCopy copy{};
    copy.srcSubresource = copy.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.srcOffset = copy.dstOffset = {r.offset.x, r.offset.y, 0};
    copy.extent = {r.extent.width, r.extent.height, 1};
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

PixelRect TemporalPass::unsettled_pixels() const {
  uint32_t tiles[4];
  std::memcpy(tiles, unsettled_.mapped(), sizeof tiles);
  if (tiles[0] > tiles[2] || tiles[1] > tiles[3]) return {};
  const int tile = int(gpu::kTemporalTile);
  return {glm::ivec2(tiles[0], tiles[1]) * tile, glm::min(glm::ivec2(tiles[2] + 1, tiles[3] + 1) * tile, size_)};
}

void TemporalPass::record_keep(VkCommandBuffer cmd, const GBufferPass& gbuffer, const TemporalImages& images,
                               const vk::Buffer& frame, const vk::Buffer& lights, gpu::TemporalPush push,
                               const PixelRect& region) const {
  if (push.image_size != size_) throw Error("TemporalPass: resize to the image first");
  if (!region.is_empty() && (glm::any(glm::lessThan(region.lo, glm::ivec2(0))) ||
                             glm::any(glm::greaterThan(region.hi, size_)) || region.lo % int(gpu::kTemporalTile) != glm::ivec2(0)))
    throw Error("TemporalPass: the keep pass's region must be whole tiles within the image");
  // (no tile listed yet, and dispatches of none; no rectangle of them)
  for (const auto& [first, count] :
       {std::pair{VkDeviceSize(0), pixel_tiles(size_)}, std::pair{quad_list_first(size_), quad_groups(size_)}}) {
    vk::clear_indirect_dispatch(cmd, tiles_, first * sizeof(uint32_t));
    vkCmdFillBuffer(cmd, tiles_.handle(), (first + 4) * sizeof(uint32_t), count * sizeof(uint32_t), 0u);
  }
  vkCmdFillBuffer(cmd, unsettled_.handle(), 0, 2 * sizeof(uint32_t), 0xFFFFFFFFu);
  vkCmdFillBuffer(cmd, unsettled_.handle(), 2 * sizeof(uint32_t), 2 * sizeof(uint32_t), 0u);
  // Outside the region every pixel is settled: history as it was is its
  // resolved accumulation and its sample (for the resolve's neighbourhoods).
  copy_rects(cmd,
             {{&images.history_color, &images.resolved_color},
              {&images.history_passes, &images.resolved_passes},
              {&images.history_moments, &images.resolved_moments},
              {&images.history_color, &images.sample_color}},
             outside(region, size_));
  vk::memory_barrier(cmd, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  keep_.bind(cmd);
  keep_.push_descriptors(cmd, bindings(gbuffer, images, frame, lights, tiles_, unsettled_));
  push.keep_origin = region.lo / int(gpu::kTemporalTile);
  keep_.push_constants(cmd, push);
  const glm::ivec2 extent = region.size();
  if (extent.x > 0 && extent.y > 0)
    vkCmdDispatch(cmd, vk::group_count(extent.x, int(gpu::kTemporalTile)),
                  vk::group_count(extent.y, int(gpu::kTemporalTile)), 1);
  vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
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
  resolve.push_descriptors(cmd, bindings(gbuffer, images, frame, lights, tiles_, unsettled_));
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
