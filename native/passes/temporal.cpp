#include "passes/temporal.h"

#include "spirv/spirv_temporal_resolve_comp.h"

namespace rtsdf {

namespace {
constexpr VkDescriptorType kImage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
constexpr VkDescriptorType kBuffer = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
}  // namespace

TemporalPass::TemporalPass(const vk::Context& context)
    : pipeline_(context, RTSDF_SPIRV(spirv_temporal_resolve_comp),
                {kImage, kImage, kImage, kImage, kImage, kImage, kBuffer, kBuffer, kImage, kImage, kImage, kImage},
                uint32_t(sizeof(gpu::TemporalPush))) {}

void TemporalPass::record(VkCommandBuffer cmd, const GBufferPass& gbuffer, const TemporalImages& images,
                          const vk::Buffer& frame, const vk::Buffer& lights, const gpu::TemporalPush& push) const {
  pipeline_.bind(cmd);
  pipeline_.push_descriptors(
      cmd, {vk::Resource::storage_image(gbuffer.position()), vk::Resource::storage_image(gbuffer.motion()),
            vk::Resource::storage_image(images.sample_color), vk::Resource::storage_image(images.sample_passes),
            vk::Resource::storage_image(images.history_color), vk::Resource::storage_image(images.history_passes),
            vk::Resource::storage_buffer(frame), vk::Resource::storage_buffer(lights),
            vk::Resource::storage_image(images.resolved_color), vk::Resource::storage_image(images.resolved_passes),
            vk::Resource::storage_image(gbuffer.normal()), vk::Resource::storage_image(gbuffer.albedo())});
  pipeline_.push_constants(cmd, push);
  vkCmdDispatch(cmd, vk::group_count(push.image_size.x, 8), vk::group_count(push.image_size.y, 8), 1);
}

}  // namespace rtsdf
