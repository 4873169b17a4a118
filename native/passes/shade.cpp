#include "passes/shade.h"

#include <algorithm>
#include <vector>

#include "error.h"
#include "shaders/shared.h"
#include "spirv/spirv_shade_comp.h"
#include "spirv/spirv_quad_visibility_comp.h"
#include "vk/context.h"

namespace rtsdf {

namespace {
constexpr VkDescriptorType kImage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
constexpr VkDescriptorType kBuffer = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
constexpr VkDescriptorType kUniform = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
// Every pass sees the same bindings (each reads those it needs).
const std::vector<VkDescriptorType> kBindings = {kImage,  kImage,  kImage,  kBuffer, kBuffer, kUniform, kImage,
                                                 kImage,  kImage,  kBuffer, kBuffer, kBuffer, kImage,  kBuffer,
                                                 kBuffer, kBuffer, kBuffer, kBuffer, kBuffer, kBuffer, kImage};
}  // namespace

ShadePass::ShadePass(const vk::Context& context)
    : context_(context),
      no_shadow_atlas_(vk::Image::plane(context, 1, 1, VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT)),
      no_shadow_tiles_(context, sizeof(gpu::ShadowTile), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                       vk::Buffer::Access::DeviceOnly) {
  vk::make_general(context, {&no_shadow_atlas_});
  // An empty box (lo above hi): trace_scene sees it and traces nothing
  // (shaders/ray_trace.glsl.h; the placeholder instances and BVHs are never read).
  gpu::BvhNode empty{};
  empty.lo = glm::vec4(1.0f);
  empty.hi = glm::vec4(-1.0f);
  empty.count = 1;
  no_rays_ = vk::upload_buffer(context, &empty, sizeof empty, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
}

const vk::Pipeline& ShadePass::pipeline(Shader shader, uint32_t mode, uint32_t stage, uint32_t field_view) {
  if (mode > gpu::kVisibilityHybrid) throw Error("ShadePass: unknown visibility method");
  std::unique_ptr<vk::Pipeline>& made = pipelines_[{uint32_t(shader), mode, stage, field_view}];
  if (!made)
    made = std::make_unique<vk::Pipeline>(
        context_, shader == Shader::Quad ? RTSDF_SPIRV(spirv_quad_visibility_comp) : RTSDF_SPIRV(spirv_shade_comp),
        kBindings, uint32_t(sizeof(gpu::ShadePush)), std::vector<uint32_t>{mode, stage, field_view});
  return *made;
}

void ShadePass::resize(glm::ivec2 size, int lights) {
  const glm::ivec2 quads = (size + 1) / 2;
  if (size != size_) {
    quad_samples_ = vk::Image::plane(context_, quads.x, quads.y, VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT);
    vk::make_general(context_, {&quad_samples_});
    const VkBufferUsageFlags list_usage =
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    fill_list_ = vk::Buffer(context_, sizeof(uint32_t) * (4 + VkDeviceSize(size.x) * VkDeviceSize(size.y)), list_usage,
                            vk::Buffer::Access::DeviceOnly);
    sky_list_ = vk::Buffer(context_, sizeof(uint32_t) * (4 + VkDeviceSize(quads.x) * VkDeviceSize(quads.y)), list_usage,
                           vk::Buffer::Access::DeviceOnly);
    quad_lights_ = {};
    size_ = size;
  }
  const VkDeviceSize light_bytes =
      sizeof(float) * VkDeviceSize(quads.x) * VkDeviceSize(quads.y) * std::clamp(lights, 1, kMaxSharedLights);
  if (!quad_lights_ || quad_lights_.size() < light_bytes)
    quad_lights_ = vk::Buffer(context_, light_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::Buffer::Access::DeviceOnly);
}

void ShadePass::record(VkCommandBuffer cmd, const ShadeInputs& in, const ShadeTargets& out, bool march_sky,
                       bool share_lights, const gpu::ShadePush& push, vk::GpuTimer* timer) {
  const GBufferPass& gbuffer = in.gbuffer;
  const MarchFields& fields = in.fields;
  const ShadowMapPass* shadow_maps = in.shadow_maps;
  const GpuScene::RayStructures* rays = in.rays;
  const uint32_t mode = push.visibility_mode;
  share_lights = share_lights && mode != gpu::kVisibilityShadowMaps && push.light_count > 0 &&
                 push.light_count <= kMaxSharedLights;
  const glm::ivec2 size = push.image_size;
  const KeptTiles* kept_tiles = push.listed_tiles ? in.kept_tiles : nullptr;
  if (push.listed_tiles && !kept_tiles) throw Error("ShadePass: listed tiles need the tile lists (TemporalPass::kept_tiles)");
  if (kept_tiles)
    vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  // Over a list of the keep pass's tiles (at that offset), or the whole image.
  auto dispatch = [&](glm::ivec2 groups, VkDeviceSize listed_at) {
    if (kept_tiles) {
      vkCmdDispatchIndirect(cmd, kept_tiles->buffer.handle(), listed_at);
    } else {
      vkCmdDispatch(cmd, uint32_t(groups.x), uint32_t(groups.y), 1);
    }
  };
  const glm::ivec2 quads = (size + 1) / 2;
  const VkDeviceSize shared_bytes = sizeof(float) * VkDeviceSize(quads.x) * VkDeviceSize(quads.y) * push.light_count;
  if (size != size_ || (share_lights && quad_lights_.size() < shared_bytes))
    throw Error("ShadePass: resize() to the image and the lights first");
  auto run = [&](const vk::Pipeline& pass, const vk::Buffer& list) {
    pass.bind(cmd);
    pass.push_descriptors(
        cmd, {vk::Resource::storage_image(gbuffer.position()), vk::Resource::storage_image(gbuffer.normal()),
              vk::Resource::storage_image(gbuffer.albedo()), vk::Resource::storage_buffer(fields.instances()),
              vk::Resource::storage_buffer(in.lights), vk::Resource::uniform_buffer(in.frame),
              vk::Resource::storage_image(out.accum_color), vk::Resource::storage_image(out.accum_passes),
              vk::Resource::storage_image(shadow_maps ? shadow_maps->moments() : no_shadow_atlas_),
              vk::Resource::storage_buffer(shadow_maps ? shadow_maps->tiles() : no_shadow_tiles_),
              vk::Resource::storage_buffer(shadow_maps ? shadow_maps->light_tiles() : no_shadow_tiles_),
              vk::Resource::storage_buffer(fields.nodes()), vk::Resource::storage_image(quad_samples_),
              vk::Resource::storage_buffer(quad_lights_), vk::Resource::storage_buffer(list),
              vk::Resource::storage_buffer(rays ? rays->top_nodes : no_rays_),
              vk::Resource::storage_buffer(rays ? rays->instances : no_shadow_tiles_),
              vk::Resource::storage_buffer(rays ? rays->bottom_nodes : no_shadow_tiles_),
              vk::Resource::storage_buffer(rays ? rays->triangles : no_shadow_tiles_),
              vk::Resource::storage_buffer(kept_tiles ? kept_tiles->buffer : no_shadow_tiles_),
              vk::Resource::storage_image(out.accum_moments)});
    pass.push_constants(cmd, push);
  };
  auto barrier = [&](VkAccessFlags dst_access, VkPipelineStageFlags dst_stage) {
    vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, dst_access,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, dst_stage);
  };
  // (the passes over a list count its groups of 64, their 8 x 8, in its first word)
  const VkAccessFlags list_access =
      VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
  const VkPipelineStageFlags list_stages = VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
  if (march_sky || share_lights) {
    // The world light's cones that march are listed by the quad pass and marched by the sky pass.
    const bool sky_list = march_sky && mode != gpu::kVisibilityRayTraced;
    if (sky_list) {
      vk::clear_indirect_dispatch(cmd, sky_list_);
      barrier(VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
    }
    run(pipeline(Shader::Quad, mode, share_lights ? gpu::kShadeShared : gpu::kShadeFull, gpu::kDebugNone), sky_list_);
    dispatch({vk::group_count(quads.x, int(gpu::kQuadGroup)), vk::group_count(quads.y, int(gpu::kQuadGroup))},
             kept_tiles ? kept_tiles->quad_dispatch : 0);
    if (sky_list) {
      barrier(list_access, list_stages);
      run(pipeline(Shader::Quad, mode, gpu::kShadeSkyList, gpu::kDebugNone), sky_list_);
      vkCmdDispatchIndirect(cmd, sky_list_.handle(), 0);
    }
    if (share_lights) vk::clear_indirect_dispatch(cmd, fill_list_);
    barrier(VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
    if (timer) timer->mark(cmd, "quad");
  }
  run(pipeline(Shader::Shade, mode, share_lights ? gpu::kShadeShared : gpu::kShadeFull, push.field_view), fill_list_);
  dispatch({vk::group_count(size.x, int(gpu::kTemporalTile)), vk::group_count(size.y, int(gpu::kTemporalTile))},
           kept_tiles ? kept_tiles->pixel_dispatch : 0);
  if (share_lights) {
    barrier(list_access, list_stages);
    run(pipeline(Shader::Shade, mode, gpu::kShadeFill, push.field_view), fill_list_);
    vkCmdDispatchIndirect(cmd, fill_list_.handle(), 0);
  }
}

}  // namespace rtsdf
