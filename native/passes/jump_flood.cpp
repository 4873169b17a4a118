#include "passes/jump_flood.h"

#include <algorithm>

#include "shaders/shared.h"
#include "spirv/spirv_jump_flood_comp.h"
#include "spirv/spirv_seed_distance_comp.h"
#include "vk/context.h"

namespace rtsdf {

JumpFloodPass::JumpFloodPass(const vk::Context& context)
    : flood_(context, RTSDF_SPIRV(spirv_jump_flood_comp),
             {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}, sizeof(gpu::JumpFloodPush)),
      distance_(context, RTSDF_SPIRV(spirv_seed_distance_comp),
                {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}, sizeof(gpu::SeedDistancePush)) {}

std::vector<int> JumpFloodPass::steps(glm::ivec3 dims) {
  int longest = std::max(dims.x, std::max(dims.y, dims.z));
  int power = 1;
  while (power < longest) power *= 2;
  std::vector<int> steps{1};
  for (int step = std::max(power / 2, 1); step >= 1; step /= 2) steps.push_back(step);
  return steps;
}

const vk::Image& JumpFloodPass::record_flood(VkCommandBuffer cmd, const vk::Image& seeds, const vk::Image& a,
                                               const vk::Image& b, vk::GpuTimer* timer) const {
  const vk::Image* source = &seeds;
  const vk::Image* target = &a;
  const vk::Image* spare = &b;
  flood_.bind(cmd);
  for (int step : steps(seeds.dims())) {
    vk::shader_writes_to_compute(cmd);
    flood_.push_descriptors(cmd, {vk::Resource::storage_image(*source), vk::Resource::storage_image(*target)});
    flood_.push_constants(cmd, gpu::JumpFloodPush{glm::ivec4(a.dims(), step)});
    vk::dispatch_grid(cmd, a.dims(), gpu::kGroupShape3D);
    if (timer) timer->mark(cmd, "jump_flood step " + std::to_string(step));
    source = target;
    std::swap(target, spare);
  }
  return *source;
}

void JumpFloodPass::record_distance(VkCommandBuffer cmd, const vk::Image& seeds, const vk::Image& distance,
                                    float voxel_size, float beta_world) const {
  vk::shader_writes_to_compute(cmd);
  distance_.bind(cmd);
  distance_.push_descriptors(cmd, {vk::Resource::storage_image(seeds), vk::Resource::storage_image(distance)});
  distance_.push_constants(cmd, gpu::SeedDistancePush{glm::ivec4(seeds.dims(), 0), glm::vec4(voxel_size, beta_world, 0, 0)});
  vk::dispatch_grid(cmd, seeds.dims(), gpu::kGroupShape3D);
}

}  // namespace rtsdf
