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
                {kImage, kImage, kImage, kBuffer, kBuffer, kBuffer, kImage, kImage, kImage, kBuffer, kBuffer, kBuffer},
                sizeof(gpu::ShadePush)),
      no_shadow_atlas_(vk::Image::plane(context, 1, 1, VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT)),
      no_shadow_tiles_(context, sizeof(gpu::ShadowTile), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                       vk::Buffer::Access::DeviceOnly) {
  vk::make_general(context, {&no_shadow_atlas_});
}

void ShadePass::record(VkCommandBuffer cmd, const GBufferPass& gbuffer, const MarchFields& fields,
                       const ShadowMapPass* shadow_maps, const vk::Buffer& lights, const vk::Buffer& frame,
                       const vk::Image& accum_color, const vk::Image& accum_passes, const gpu::ShadePush& push) const {
  pipeline_.bind(cmd);
  pipeline_.push_descriptors(
      cmd, {vk::Resource::storage_image(gbuffer.position()), vk::Resource::storage_image(gbuffer.normal()),
            vk::Resource::storage_image(gbuffer.albedo()), vk::Resource::storage_buffer(fields.instances()),
            vk::Resource::storage_buffer(lights), vk::Resource::storage_buffer(frame),
            vk::Resource::storage_image(accum_color), vk::Resource::storage_image(accum_passes),
            vk::Resource::storage_image(shadow_maps ? shadow_maps->moments() : no_shadow_atlas_),
            vk::Resource::storage_buffer(shadow_maps ? shadow_maps->tiles() : no_shadow_tiles_),
            vk::Resource::storage_buffer(shadow_maps ? shadow_maps->light_tiles() : no_shadow_tiles_),
            vk::Resource::storage_buffer(fields.nodes())});
  pipeline_.push_constants(cmd, push);
  vkCmdDispatch(cmd, vk::group_count(push.image.x, 8), vk::group_count(push.image.y, 8), 1);
}

}  // namespace rtsdf
