#include "passes/field_pack.h"

#include "spirv/spirv_field_brick_slots_comp.h"
#include "spirv/spirv_field_bricks_comp.h"
#include "spirv/spirv_field_far_comp.h"
#include "vk/context.h"

namespace rtsdf {

namespace {
constexpr VkDescriptorType kImage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
constexpr VkDescriptorType kBuffer = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
}  // namespace

FieldPackPass::FieldPackPass(const vk::Context& context)
    : far_(context, RTSDF_SPIRV(spirv_field_far_comp), {kImage}, sizeof(gpu::FieldPackPush)),
      slots_(context, RTSDF_SPIRV(spirv_field_brick_slots_comp), {kImage, kBuffer}, sizeof(gpu::FieldPackPush)),
      bricks_(context, RTSDF_SPIRV(spirv_field_bricks_comp), {kImage, kBuffer}, sizeof(gpu::FieldPackPush)) {}

void FieldPackPass::record(VkCommandBuffer cmd, const gpu::FieldPackPush& push, const vk::Image& coarse,
                           const vk::Image* fine, glm::ivec3 bricks, const vk::Buffer& stored_bricks) const {
  far_.bind(cmd);
  far_.push_descriptors(cmd, {vk::Resource::storage_image(coarse)});
  far_.push_constants(cmd, push);
  vk::dispatch_grid(cmd, glm::ivec3((push.coarse_dims.x + 1) / 2, push.coarse_dims.y, push.coarse_dims.z), gpu::kGroupShape3D);
  if (fine) {
    slots_.bind(cmd);
    slots_.push_descriptors(cmd, {vk::Resource::storage_image(coarse), vk::Resource::storage_buffer(stored_bricks)});
    slots_.push_constants(cmd, push);
    vkCmdDispatch(cmd, vk::group_count(bricks.x * bricks.y * bricks.z, 64), 1, 1);
    vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
    bricks_.bind(cmd);
    bricks_.push_descriptors(cmd, {vk::Resource::storage_image(*fine), vk::Resource::storage_buffer(stored_bricks)});
    bricks_.push_constants(cmd, push);
    vkCmdDispatchIndirect(cmd, stored_bricks.handle(), 0);
  }
  vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT);
}

}  // namespace rtsdf
