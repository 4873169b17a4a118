#include "passes/shade.h"

#include "shaders/shared.h"
#include "spirv/spirv_shade_comp.h"
#include "vk/context.h"

namespace rtsdf {

namespace {
constexpr VkDescriptorType kImage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
constexpr VkDescriptorType kBuffer = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
}  // namespace

ShadePass::ShadePass(const vk::Context& context)
    : pipeline_(context, RTSDF_SPIRV(spirv_shade_comp),
                {kImage, kImage, kImage, kImage, kBuffer, kBuffer, kImage, kImage}, sizeof(gpu::ShadePush)) {}

void ShadePass::record(VkCommandBuffer cmd, const GBufferPass& gbuffer, const vk::Image& fine,
                       const vk::Buffer& lights, const vk::Buffer& frame, const vk::Image& accum_color,
                       const vk::Image& accum_passes, const gpu::ShadePush& push) const {
  pipeline_.bind(cmd);
  pipeline_.push_descriptors(
      cmd, {vk::Resource::storage_image(gbuffer.position()), vk::Resource::storage_image(gbuffer.normal()),
            vk::Resource::storage_image(gbuffer.albedo()), vk::Resource::storage_image(fine),
            vk::Resource::storage_buffer(lights), vk::Resource::storage_buffer(frame),
            vk::Resource::storage_image(accum_color), vk::Resource::storage_image(accum_passes)});
  pipeline_.push_constants(cmd, push);
  vkCmdDispatch(cmd, vk::group_count(push.image.x, 8), vk::group_count(push.image.y, 8), 1);
}

}  // namespace rtsdf
