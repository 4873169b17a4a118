#include "passes/exact_distance.h"

#include <algorithm>

#include "error.h"
#include "shaders/shared.h"
#include "spirv/spirv_exact_distance_comp.h"
#include "vk/context.h"

namespace rtsdf {

namespace {
const std::vector<VkDescriptorType> kBindings = {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                                                 VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
constexpr uint32_t kLinesPerGroup = 64;  // (the shader's local size)
}  // namespace

ExactDistancePass::ExactDistancePass(const vk::Context& context) : context_(context) {}

const ExactDistancePass::AxisPipelines& ExactDistancePass::pipelines(int longest) {
  int line = 16;
  while (line < longest) line *= 2;
  if (line > (1 << gpu::kSeedBits)) throw Error("exact distance: a grid axis is longer than seeds can hold");
  AxisPipelines& made = by_line_[line];
  for (uint32_t axis = 0; axis < 3; ++axis)
    if (!made[axis])
      made[axis] = std::make_unique<vk::Pipeline>(context_, RTSDF_SPIRV(spirv_exact_distance_comp), kBindings,
                                                  uint32_t(sizeof(gpu::SeedDistancePush)),
                                                  std::vector<uint32_t>{axis, uint32_t(line)});
  return made;
}

void ExactDistancePass::record(VkCommandBuffer cmd, const vk::Image& seeds, const vk::Image& a, const vk::Image& b,
                               const vk::Image& distance, float voxel_size, float beta_world,
                               vk::GpuTimer* timer) {
  const glm::ivec3 dims = seeds.dims();
  const AxisPipelines& axis = pipelines(std::max(dims.x, std::max(dims.y, dims.z)));
  const gpu::SeedDistancePush push{glm::ivec4(dims, 0), glm::vec4(voxel_size, beta_world, 0, 0)};
  const struct {
    const vk::Pipeline& pipeline;
    const vk::Image& in;
    const vk::Image& out;
    int lines;  // the grid's lines along the pass's axis
  } passes[] = {{*axis[0], seeds, a, dims.y * dims.z}, {*axis[1], a, b, dims.z * dims.x}, {*axis[2], b, a, dims.x * dims.y}};
  for (const auto& pass : passes) {
    vk::shader_writes_to_compute(cmd);
    pass.pipeline.bind(cmd);
    pass.pipeline.push_descriptors(cmd, {vk::Resource::storage_image(pass.in), vk::Resource::storage_image(pass.out),
                                         vk::Resource::storage_image(distance)});
    pass.pipeline.push_constants(cmd, push);
    vkCmdDispatch(cmd, vk::group_count(pass.lines, int(kLinesPerGroup)), 1, 1);
  }
  if (timer) timer->mark(cmd, "exact distance");
}

}  // namespace rtsdf
