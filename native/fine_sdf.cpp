#include "fine_sdf.h"

#include <cmath>
#include <cstring>

#include "shaders/shared.h"
#include "vk/context.h"

namespace rtsdf {

GridSpec FineSdf::fit(const GridSpec& coarse, int fine_resolution) {
  const int coarse_longest = std::max(coarse.dims.x, std::max(coarse.dims.y, coarse.dims.z));
  if (fine_resolution < coarse_longest || fine_resolution > int(gpu::kMaxGridResolution))
    throw Error("fine resolution " + std::to_string(fine_resolution) + " is out of range: use " +
                std::to_string(coarse_longest) + " (the coarse resolution) to " +
                std::to_string(gpu::kMaxGridResolution));
  GridSpec fine;
  fine.origin = coarse.origin;
  fine.voxel_size = coarse.voxel_size * float(coarse_longest) / float(fine_resolution);
  const glm::vec3 extent = glm::vec3(coarse.dims) * coarse.voxel_size;
  for (int a = 0; a < 3; ++a)
    fine.dims[a] = std::min(fine_resolution, int(std::ceil(extent[a] / fine.voxel_size - 1e-3f)));
  return fine;
}

FineSdf::FineSdf(const vk::Context& context, std::shared_ptr<const FineTracePass> pass)
    : context_(context),
      pass_(pass ? std::move(pass) : std::make_shared<const FineTracePass>(context)),
      timer_(context, 8),
      traced_(context, 3 * sizeof(uint32_t), VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::Buffer::Access::HostVisible) {
  std::memset(traced_.mapped(), 0, 3 * sizeof(uint32_t));
}

void FineSdf::allocate(const GridSpec& grid) {
  if (distance_.dims() == grid.dims && grid.origin == grid_.origin && grid.voxel_size == grid_.voxel_size) return;
  const size_t needed = grid.voxel_count() * kBytesPerTexel;
  if (needed > context_.device_local_heap_bytes() * 3 / 4)
    throw Error("the fine grid needs " + std::to_string(needed >> 20) + " MiB: lower the fine resolution");
  const VkImageUsageFlags usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  distance_ = vk::Image(context_, grid.dims, VK_FORMAT_R32_SFLOAT, usage);
  history_ = vk::Image(context_, grid.dims, VK_FORMAT_R32G32B32A32_SFLOAT, usage);
  trace_list_ = vk::Buffer(context_, (grid.voxel_count() + 2) * sizeof(uint32_t),  // (two counts, then the texels)
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                               VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                           vk::Buffer::Access::DeviceOnly);
  // Room for one texel of the grid in four doubted (fine_signs.comp):
  // beyond it the trace settles them itself.
  doubts_ = vk::Buffer(context_, (4 + grid.voxel_count() / 4 + kDoubtRoom) * sizeof(uint32_t),
                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                           VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                       vk::Buffer::Access::DeviceOnly);
  dispatch_ = vk::Buffer(context_, 8 * sizeof(uint32_t),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                         vk::Buffer::Access::DeviceOnly);
  const glm::ivec3 bricks = bricks_of(grid.dims);
  const size_t brick_count = size_t(bricks.x) * bricks.y * bricks.z;
  brick_state_ = vk::Buffer(context_, brick_count * 2 * sizeof(uint32_t),
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::Buffer::Access::DeviceOnly);
  near_bricks_ = vk::Buffer(context_, (4 + brick_count) * sizeof(uint32_t),
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                                VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                            vk::Buffer::Access::DeviceOnly);
  vk::make_general(context_, {&distance_, &history_});
  grid_ = grid;
  frame_ = 0;
}

void FineSdf::release() {
  distance_ = {};
  history_ = {};
  trace_list_ = {};
  dispatch_ = {};
  doubts_ = {};
  brick_state_ = {};
  near_bricks_ = {};
  grid_ = {};
  frame_ = 0;
}

void FineSdf::update(GpuScene& scene, const CoarseSdf& coarse, const GridSpec& fine_grid,
                     const FineTraceSettings& settings, const Bounds* changed) {
  update(scene.ray_structures().targets(), coarse, fine_grid, settings, changed);
}

void FineSdf::update(const GpuScene::RayTargets& rays, const CoarseSdf& coarse, const GridSpec& fine_grid,
                     const FineTraceSettings& settings, const Bounds* changed, float surface_move) {
  if (settings.rays_per_texel < 1 || settings.rays_per_texel > 1024) throw Error("rays per texel must be 1 to 1024");
  if (!(settings.decay >= 0.0f && settings.decay < 1.0f)) throw Error("decay (alpha) must be in [0, 1)");
  if (settings.interleave < 1 || settings.interleave > 64) throw Error("interleave must be 1 to 64");
  if (!(settings.trace_band >= 0.0f && settings.trace_band <= 64.0f)) throw Error("trace band d must be 0 to 64 coarse voxels");
  allocate(fine_grid);
  context_.submit_and_wait([&](VkCommandBuffer cmd) {
    timer_.begin(cmd);
    pass_->record(cmd, rays,
                  {coarse.grid(), coarse.distance(), coarse.beta_world(), grid_, distance_, history_, trace_list_, dispatch_,
                   brick_state_, near_bricks_, doubts_},
                  settings, {frame_, frame_ == 0, changed, surface_move}, &timer_);
    vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
    // (the dispatch buffer's words 3 and 4: texels traced and improved; the doubts' first: their count)
    VkBufferCopy counts{3 * sizeof(uint32_t), 0, 2 * sizeof(uint32_t)};
    vkCmdCopyBuffer(cmd, dispatch_.handle(), traced_.handle(), 1, &counts);
    VkBufferCopy doubted{0, 2 * sizeof(uint32_t), sizeof(uint32_t)};
    vkCmdCopyBuffer(cmd, doubts_.handle(), traced_.handle(), 1, &doubted);
    vk::memory_barrier(cmd, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT);
  });
  stats_ = {};
  for (const vk::GpuTimer::Span& span : timer_.read()) {
    if (span.label == "fine classify") stats_.classify_ms = span.ms;
    if (span.label == "fine trace") stats_.trace_ms = span.ms;
  }
  frame_++;
}

std::vector<float> FineSdf::read_distance() const {
  vk::Buffer readback = vk::download_image(context_, distance_, sizeof(float));
  std::vector<float> values(distance_.texel_count());
  std::memcpy(values.data(), readback.mapped(), values.size() * sizeof(float));
  return values;
}

uint32_t FineSdf::read_count(int which) const {
  uint32_t counts[3] = {};  // texels traced, improved, doubted
  std::memcpy(counts, traced_.mapped(), sizeof counts);
  return counts[which];
}

}  // namespace rtsdf
