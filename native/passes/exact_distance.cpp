#include "passes/exact_distance.h"

#include "shaders/shared.h"
#include "spirv/spirv_exact_distance_comp.h"
#include "vk/context.h"

namespace rtsdf {

namespace {
const std::vector<VkDescriptorType> kBindings = {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                                                 VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
constexpr uint32_t kLinesPerGroup = 64;  // (the shader's local size)
}  // namespace

ExactDistancePass::ExactDistancePass(const vk::Context& context)
    : axis_x_(context, RTSDF_SPIRV(spirv_exact_distance_comp), kBindings, sizeof(gpu::SeedDistancePush), {0u}),
      axis_y_(context, RTSDF_SPIRV(spirv_exact_distance_comp), kBindings, sizeof(gpu::SeedDistancePush), {1u}),
      axis_z_(context, RTSDF_SPIRV(spirv_exact_distance_comp), kBindings, sizeof(gpu::SeedDistancePush), {2u}) {}

void ExactDistancePass::record(VkCommandBuffer cmd, const vk::Image& seeds, const vk::Image& a, const vk::Image& b,
                               const vk::Image& distance, float voxel_size, float beta_world,
                               vk::GpuTimer* timer) const {
  const glm::ivec3 dims = seeds.dims();
  const gpu::SeedDistancePush push{glm::ivec4(dims, 0), glm::vec4(voxel_size, beta_world, 0, 0)};
  const struct {
    const vk::Pipeline& pipeline;
    const vk::Image& in;
    const vk::Image& out;
    int lines;  // the grid's lines along the pass's axis
  } passes[] = {{axis_x_, seeds, a, dims.y * dims.z}, {axis_y_, a, b, dims.z * dims.x}, {axis_z_, b, a, dims.x * dims.y}};
  for (const auto& pass : passes) {
    vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
    pass.pipeline.bind(cmd);
    pass.pipeline.push_descriptors(cmd, {vk::Resource::storage_image(pass.in), vk::Resource::storage_image(pass.out),
                                         vk::Resource::storage_image(distance)});
    pass.pipeline.push_constants(cmd, push);
    vkCmdDispatch(cmd, vk::group_count(pass.lines, int(kLinesPerGroup)), 1, 1);
  }
  if (timer) timer->mark(cmd, "exact distance");
}

}  // namespace rtsdf
