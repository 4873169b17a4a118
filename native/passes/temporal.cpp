#include "passes/temporal.h"

#include "spirv/spirv_temporal_keep_comp.h"
#include "spirv/spirv_temporal_resolve_comp.h"

namespace rtsdf {

namespace {
constexpr VkDescriptorType kImage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
constexpr VkDescriptorType kBuffer = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
}  // namespace

TemporalPass::TemporalPass(const vk::Context& context)
    : keep_(context, RTSDF_SPIRV(spirv_temporal_keep_comp),
            {kImage, kImage, kImage, kImage, kImage, kImage, kBuffer, kBuffer, kImage, kImage},
            uint32_t(sizeof(gpu::TemporalPush))),
      resolve_(context, RTSDF_SPIRV(spirv_temporal_resolve_comp),
               {kImage, kImage, kImage, kImage, kImage, kImage, kBuffer, kBuffer, kImage, kImage, kImage, kImage},
               uint32_t(sizeof(gpu::TemporalPush))) {}

namespace {
// Bindings 0 to 9, the same in both passes: the G-buffer's position and
// motion, this frame's sample, history, the frame, the lights and the resolved accumulation.
std::vector<vk::Resource> shared_bindings(const GBufferPass& gbuffer, const TemporalImages& images,
                                          const vk::Buffer& frame, const vk::Buffer& lights) {
  return {vk::Resource::storage_image(gbuffer.position()),     vk::Resource::storage_image(gbuffer.motion()),
          vk::Resource::storage_image(images.sample_color),    vk::Resource::storage_image(images.sample_passes),
          vk::Resource::storage_image(images.history_color),   vk::Resource::storage_image(images.history_passes),
          vk::Resource::storage_buffer(frame),                 vk::Resource::storage_buffer(lights),
          vk::Resource::storage_image(images.resolved_color),  vk::Resource::storage_image(images.resolved_passes)};
}
}  // namespace

void TemporalPass::record_keep(VkCommandBuffer cmd, const GBufferPass& gbuffer, const TemporalImages& images,
                               const vk::Buffer& frame, const vk::Buffer& lights,
                               const gpu::TemporalPush& push) const {
  keep_.bind(cmd);
  keep_.push_descriptors(cmd, shared_bindings(gbuffer, images, frame, lights));
  keep_.push_constants(cmd, push);
  vkCmdDispatch(cmd, vk::group_count(push.image_size.x, 8), vk::group_count(push.image_size.y, 8), 1);
}

void TemporalPass::record(VkCommandBuffer cmd, const GBufferPass& gbuffer, const TemporalImages& images,
                          const vk::Buffer& frame, const vk::Buffer& lights, const gpu::TemporalPush& push) const {
  std::vector<vk::Resource> bindings = shared_bindings(gbuffer, images, frame, lights);
  bindings.insert(bindings.end(),
                  {vk::Resource::storage_image(gbuffer.normal()), vk::Resource::storage_image(gbuffer.albedo())});
  resolve_.bind(cmd);
  resolve_.push_descriptors(cmd, bindings);
  resolve_.push_constants(cmd, push);
  vkCmdDispatch(cmd, vk::group_count(push.image_size.x, 8), vk::group_count(push.image_size.y, 8), 1);
}

}  // namespace rtsdf
