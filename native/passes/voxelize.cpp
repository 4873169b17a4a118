#include "passes/voxelize.h"

#include <algorithm>

#include "shaders/shared.h"
#include "spirv/spirv_voxelize_frag.h"
#include "spirv/spirv_voxelize_splat_comp.h"
#include "spirv/spirv_voxelize_vert.h"
#include "vk/context.h"

namespace rtsdf {

VoxelizePass::VoxelizePass(const vk::Context& context)
    : context_(context),
      pipeline_(context, RTSDF_SPIRV(spirv_voxelize_vert), RTSDF_SPIRV(spirv_voxelize_frag),
                {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                sizeof(gpu::VoxelizePush)),
      splat_(context, RTSDF_SPIRV(spirv_voxelize_splat_comp),
             {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
             sizeof(gpu::VoxelizePush)) {}

void VoxelizePass::record(VkCommandBuffer cmd, const GpuScene& scene, const GridSpec& grid, const vk::Image& seeds,
                          const std::vector<VoxelizeItem>& items) {
  // Each triangle is drawn along its own dominant axis into one of three
  // squares side by side, each big enough for any face of the grid. The
  // framebuffer only grows (grids of many sizes share it; the viewport
  // picks the part used). A growth frees the old one: record one grid per
  // submission, as CoarseSdf::build does.
  uint32_t edge = uint32_t(std::max(grid.dims.x, std::max(grid.dims.y, grid.dims.z)));
  const uint32_t width = 3 * edge;
  if (!framebuffer_ || framebuffer_edge_ < edge) {
    framebuffer_ = std::make_unique<vk::Framebuffer>(context_, pipeline_.render_pass(), width, edge);
    framebuffer_edge_ = edge;
  }

  VkClearColorValue empty{};
  empty.uint32[0] = gpu::kNoSeed;
  VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vk::memory_barrier(cmd, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT);
  vkCmdClearColorImage(cmd, seeds.handle(), VK_IMAGE_LAYOUT_GENERAL, &empty, 1, &all);
  vk::memory_barrier(cmd, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT);

  VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  begin.renderPass = pipeline_.render_pass();
  begin.framebuffer = framebuffer_->handle();
  begin.renderArea = {{0, 0}, {width, edge}};
  vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
  VkViewport viewport{0.0f, 0.0f, float(width), float(edge), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, {width, edge}};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
  pipeline_.bind(cmd);
  pipeline_.push_descriptors(cmd, {vk::Resource::storage_buffer(scene.positions()),
                                   vk::Resource::storage_buffer(scene.indices()),
                                   vk::Resource::storage_image(seeds)});
  const glm::mat4 world_to_voxel = grid.world_to_voxel();
  auto push_for = [&](const VoxelizeItem& item) {
    const GpuMeshRange& mesh = scene.meshes()[item.mesh];
    gpu::VoxelizePush push{};
    push.object_to_voxel = world_to_voxel * item.object_to_grid_space;
    push.dims = glm::ivec4(grid.dims, int(edge));
    push.first_index = mesh.first_index;
    push.base_vertex = mesh.base_vertex;
    push.triangle_count = mesh.triangle_count;
    return push;
  };
  for (const VoxelizeItem& item : items) {
    gpu::VoxelizePush push = push_for(item);
    if (push.triangle_count == 0) continue;
    pipeline_.push_constants(cmd, push);
    vkCmdDraw(cmd, 3 * push.triangle_count, 1, 0, 0);
  }
  vkCmdEndRenderPass(cmd);

  splat_.bind(cmd);
  splat_.push_descriptors(cmd, {vk::Resource::storage_buffer(scene.positions()),
                                vk::Resource::storage_buffer(scene.indices()), vk::Resource::storage_image(seeds)});
  for (const VoxelizeItem& item : items) {
    gpu::VoxelizePush push = push_for(item);
    if (push.triangle_count == 0) continue;
    splat_.push_constants(cmd, push);
    vkCmdDispatch(cmd, vk::group_count(int(push.triangle_count), 64), 1, 1);
  }
}

}  // namespace rtsdf
