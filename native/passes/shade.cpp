#include "passes/shade.h"

#include <vector>

#include "error.h"
#include "shaders/shared.h"
#include "spirv/spirv_shade_comp.h"
#include "spirv/spirv_sky_comp.h"
#include "vk/context.h"

namespace rtsdf {

namespace {
constexpr VkDescriptorType kImage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
constexpr VkDescriptorType kBuffer = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
// Both passes see the same bindings (each reads those it needs).
const std::vector<VkDescriptorType> kBindings = {kImage, kImage,  kImage,  kBuffer, kBuffer, kBuffer, kImage,
                                                 kImage, kImage,  kBuffer, kBuffer, kBuffer, kImage};
}  // namespace

ShadePass::ShadePass(const vk::Context& context)
    : context_(context),
      no_shadow_atlas_(vk::Image::plane(context, 1, 1, VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT)),
      no_shadow_tiles_(context, sizeof(gpu::ShadowTile), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                       vk::Buffer::Access::DeviceOnly) {
  vk::make_general(context, {&no_shadow_atlas_});
}

void ShadePass::record(VkCommandBuffer cmd, const GBufferPass& gbuffer, const MarchFields& fields,
                       const ShadowMapPass* shadow_maps, const vk::Buffer& lights, const vk::Buffer& frame,
                       const vk::Image& accum_color, const vk::Image& accum_passes, const vk::Image& sky_samples,
                       bool march_sky, const gpu::ShadePush& push) {
  const uint32_t mode = push.visibility.x;
  if (mode >= passes_.size()) throw Error("ShadePass: unknown visibility method");
  Passes& passes = passes_[mode];
  if (!passes.shade) {
    passes.sky = std::make_unique<vk::Pipeline>(context_, RTSDF_SPIRV(spirv_sky_comp), kBindings,
                                                uint32_t(sizeof(gpu::ShadePush)), std::vector<uint32_t>{mode});
    passes.shade = std::make_unique<vk::Pipeline>(context_, RTSDF_SPIRV(spirv_shade_comp), kBindings,
                                                  uint32_t(sizeof(gpu::ShadePush)), std::vector<uint32_t>{mode});
  }
  for (const vk::Pipeline* pass : {passes.sky.get(), passes.shade.get()}) {
    const bool sky = pass == passes.sky.get();
    if (sky && !march_sky) continue;
    pass->bind(cmd);
    pass->push_descriptors(
        cmd, {vk::Resource::storage_image(gbuffer.position()), vk::Resource::storage_image(gbuffer.normal()),
              vk::Resource::storage_image(gbuffer.albedo()), vk::Resource::storage_buffer(fields.instances()),
              vk::Resource::storage_buffer(lights), vk::Resource::storage_buffer(frame),
              vk::Resource::storage_image(accum_color), vk::Resource::storage_image(accum_passes),
              vk::Resource::storage_image(shadow_maps ? shadow_maps->moments() : no_shadow_atlas_),
              vk::Resource::storage_buffer(shadow_maps ? shadow_maps->tiles() : no_shadow_tiles_),
              vk::Resource::storage_buffer(shadow_maps ? shadow_maps->light_tiles() : no_shadow_tiles_),
              vk::Resource::storage_buffer(fields.nodes()), vk::Resource::storage_image(sky_samples)});
    pass->push_constants(cmd, push);
    const glm::ivec2 size = sky ? (glm::ivec2(push.image) + 1) / 2 : glm::ivec2(push.image);
    vkCmdDispatch(cmd, vk::group_count(size.x, 8), vk::group_count(size.y, 8), 1);
    if (sky)
      vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  }
}

}  // namespace rtsdf
