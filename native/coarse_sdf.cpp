#include "coarse_sdf.h"

#include <cstring>

#include "vk/context.h"

namespace rtsdf {

namespace {

const VkImageUsageFlags kGridUsage =
    VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;

template <typename T>
std::vector<T> read_image(const vk::Context& context, const vk::Image& image) {
  vk::Buffer readback = vk::download_image(context, image, sizeof(T));
  std::vector<T> values(image.texel_count());
  std::memcpy(values.data(), readback.mapped(), values.size() * sizeof(T));
  return values;
}

}  // namespace

size_t coarse_sdf_bytes(const GridSpec& grid) { return grid.voxel_count() * 4 * sizeof(uint32_t); }

CoarseSdf::CoarseSdf(const vk::Context& context, std::shared_ptr<CoarsePasses> passes)
    : context_(context),
      passes_(passes ? std::move(passes) : std::make_shared<CoarsePasses>(context)),
      timer_(context, 64) {}

void CoarseSdf::allocate(const GridSpec& grid) {
  if (distance_.dims() == grid.dims) return;
  const size_t needed = coarse_sdf_bytes(grid);
  const size_t available = context_.device_local_heap_bytes();
  if (needed > available * 3 / 4)
    throw Error("a " + std::to_string(grid.dims.x) + "x" + std::to_string(grid.dims.y) + "x" +
                std::to_string(grid.dims.z) + " grid needs " + std::to_string(needed >> 20) + " MiB but the device " +
                context_.info().name + " has " + std::to_string(available >> 20) + " MiB: lower the resolution");
  distance_ = {};
  seeds_ = vk::Image(context_, grid.dims, VK_FORMAT_R32_UINT, kGridUsage);
  flood_a_ = vk::Image(context_, grid.dims, VK_FORMAT_R32_UINT, kGridUsage);
  flood_b_ = vk::Image(context_, grid.dims, VK_FORMAT_R32_UINT, kGridUsage);
  distance_ = vk::Image(context_, grid.dims, VK_FORMAT_R32_SFLOAT, kGridUsage);
  vk::make_general(context_, {&seeds_, &flood_a_, &flood_b_, &distance_});
}

void CoarseSdf::release() {
  seeds_ = {};
  flood_a_ = {};
  flood_b_ = {};
  distance_ = {};
  grid_ = {};
}

void CoarseSdf::build(const GpuScene& scene, const GridSpec& grid, float beta_voxels) {
  std::vector<VoxelizeItem> items;
  for (uint32_t i : scene.shadow_casters())
    items.push_back({scene.instances()[i].mesh, scene.instances()[i].object_to_world});
  build(scene, grid, beta_voxels, items, Transform::JumpFlood);
}

void CoarseSdf::build_mesh(const GpuScene& scene, uint32_t mesh, const GridSpec& grid, float beta_voxels) {
  build(scene, grid, beta_voxels, {{mesh, glm::mat4(1.0f)}}, Transform::Exact);
}

void CoarseSdf::build(const GpuScene& scene, const GridSpec& grid, float beta_voxels,
                      const std::vector<VoxelizeItem>& items, Transform transform) {
  allocate(grid);
  grid_ = grid;
  beta_world_ = beta_voxels * grid.voxel_size;
  context_.submit_and_wait([&](VkCommandBuffer cmd) {
    timer_.begin(cmd);
    passes_->voxelize.record(cmd, scene, grid, seeds_, items);
    timer_.mark(cmd, "voxelize");
    if (transform == Transform::Exact) {
      passes_->exact_distance.record(cmd, seeds_, flood_a_, flood_b_, distance_, grid.voxel_size, beta_world_, &timer_);
    } else {
      const vk::Image& nearest = passes_->jump_flood.record_flood(cmd, seeds_, flood_a_, flood_b_, &timer_);
      passes_->jump_flood.record_distance(cmd, nearest, distance_, grid.voxel_size, beta_world_);
      timer_.mark(cmd, "seed distance");
    }
  });
  timings_ = {};
  for (const vk::GpuTimer::Span& span : timer_.read()) {
    timings_.gpu_total_ms += span.ms;
    if (span.label == "voxelize") {
      timings_.voxelize_ms = span.ms;
    } else if (span.label == "exact distance") {
      timings_.exact_distance_ms = span.ms;
    } else if (span.label == "seed distance") {
      timings_.jump_flood_ms += span.ms;
    } else if (span.label.rfind("jump_flood", 0) == 0) {
      timings_.jump_flood_ms += span.ms;
      timings_.pass_ms.push_back(span.ms);
    }
  }
}

std::vector<float> CoarseSdf::read_distance() const { return read_image<float>(context_, distance_); }
std::vector<uint32_t> CoarseSdf::read_seeds() const { return read_image<uint32_t>(context_, seeds_); }

}  // namespace rtsdf
