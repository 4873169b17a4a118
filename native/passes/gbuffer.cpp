#include "passes/gbuffer.h"

#include <cmath>
#include <glm/gtc/matrix_access.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "shaders/shared.h"
#include "spirv/spirv_gbuffer_deforming_frag.h"
#include "spirv/spirv_gbuffer_deforming_vert.h"
#include "spirv/spirv_gbuffer_frag.h"
#include "spirv/spirv_gbuffer_one_color_frag.h"
#include "spirv/spirv_gbuffer_one_color_vert.h"
#include "spirv/spirv_gbuffer_vert.h"
#include "error.h"
#include "march_fields.h"
#include "vk/context.h"

namespace rtsdf {

namespace {
constexpr VkFormat kColor = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kDepth = VK_FORMAT_D32_SFLOAT;
// The scene's vertex and material buffers, and the frame (binding 1: a
// uniform buffer, read alike by every vertex and fragment); binding 8: the
// vertices before a deformation.
const std::vector<VkDescriptorType> kBindings = [] {
  std::vector<VkDescriptorType> bindings(9, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  bindings[1] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
  return bindings;
}();
const vk::RenderTargets kTargets{{kColor, kColor, kColor, kColor}, kDepth};

// An affine transform as GBufferPush holds it: the rows of its 3x4 matrix.
glm::mat3x4 affine_rows(const glm::mat4& m) { return glm::mat3x4(glm::row(m, 0), glm::row(m, 1), glm::row(m, 2)); }

}  // namespace

std::vector<glm::mat4> world_motions(const std::vector<glm::mat4>& before, const std::vector<glm::mat4>& now) {
  if (before.size() != now.size()) throw Error("world_motions: one placement before per placement now");
  std::vector<glm::mat4> motions(now.size(), glm::mat4(1.0f));
  for (size_t i = 0; i < now.size(); ++i) {
    if (before[i] == now[i]) continue;
    const glm::vec2 stretch = singular_value_range(glm::mat3(now[i]));
    motions[i] = stretch.x > kDegenerateScale * stretch.y
                     ? glm::mat4(glm::dmat4(before[i]) * glm::inverse(glm::dmat4(now[i])))
                     : glm::translate(glm::mat4(1.0f), glm::vec3(before[i][3] - now[i][3]));
  }
  return motions;
}

GBufferPass::GBufferPass(const vk::Context& context)
    : context_(context),
      one_color_(context, RTSDF_SPIRV(spirv_gbuffer_one_color_vert), RTSDF_SPIRV(spirv_gbuffer_one_color_frag), kBindings,
                 sizeof(gpu::GBufferPush), kTargets),
      material_slots_(context, RTSDF_SPIRV(spirv_gbuffer_vert), RTSDF_SPIRV(spirv_gbuffer_frag), kBindings,
                      sizeof(gpu::GBufferPush), kTargets),
      deforming_(context, RTSDF_SPIRV(spirv_gbuffer_deforming_vert), RTSDF_SPIRV(spirv_gbuffer_deforming_frag), kBindings,
                 sizeof(gpu::GBufferPush), kTargets) {}

void GBufferPass::resize(int width, int height) {
  if (width == width_ && height == height_) return;
  const VkImageUsageFlags usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT;
  framebuffer_.reset();
  position_ = vk::Image::plane(context_, width, height, kColor, usage);
  normal_ = vk::Image::plane(context_, width, height, kColor, usage);
  albedo_ = vk::Image::plane(context_, width, height, kColor, usage);
  motion_ = vk::Image::plane(context_, width, height, kColor, usage | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);  // (read back for inspection)
  depth_ = vk::Image::plane(context_, width, height, kDepth, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT);
  framebuffer_ = std::make_unique<vk::Framebuffer>(
      context_, one_color_.render_pass(), uint32_t(width), uint32_t(height),
      std::vector<VkImageView>{position_.view(), normal_.view(), albedo_.view(), motion_.view(), depth_.view()});
  width_ = width;
  height_ = height;
}

void GBufferPass::record(VkCommandBuffer cmd, const GpuScene& scene, const vk::Buffer& frame,
                         const std::vector<float>& field_voxels, const std::vector<glm::mat4>& motions,
                         const std::vector<uint8_t>& deformed, const PixelRect& region) const {
  if (field_voxels.size() != scene.instances().size()) throw Error("GBufferPass: one field voxel per instance");
  if (motions.size() != scene.instances().size() || deformed.size() != scene.instances().size())
    throw Error("GBufferPass: one motion per instance");
  if (region.is_empty()) return;
  const VkRect2D drawn{{region.lo.x, region.lo.y}, {uint32_t(region.size().x), uint32_t(region.size().y)}};
  VkClearValue clears[5]{};
  clears[4].depthStencil = {1.0f, 0};
  VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  begin.renderPass = one_color_.render_pass();
  begin.framebuffer = framebuffer_->handle();
  begin.renderArea = drawn;
  begin.clearValueCount = 5;
  begin.pClearValues = clears;
  vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
  VkViewport viewport{0.0f, 0.0f, float(width_), float(height_), 0.0f, 1.0f};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &drawn);
  vkCmdBindIndexBuffer(cmd, scene.indices().handle(), 0, VK_INDEX_TYPE_UINT32);
  const std::vector<vk::Resource> resources{
      vk::Resource::storage_buffer(scene.positions()),        vk::Resource::uniform_buffer(frame),
      vk::Resource::storage_buffer(scene.normals()),          vk::Resource::storage_buffer(scene.uvs()),
      vk::Resource::storage_buffer(scene.vertex_materials()), vk::Resource::storage_buffer(scene.materials()),
      vk::Resource::storage_buffer(scene.texels()),           vk::Resource::storage_buffer(scene.colors()),
      vk::Resource::storage_buffer(scene.previous_positions())};
  const vk::Pipeline* bound = nullptr;
  for (size_t i = 0; i < scene.instances().size(); ++i) {
    const Instance& instance = scene.instances()[i];
    const GpuMeshRange& mesh = scene.meshes()[instance.mesh];
    if (mesh.triangle_count == 0 || !instance.visible_to_camera) continue;
    const glm::uvec2 slots = scene.material_range(uint32_t(i));
    const vk::Pipeline& pipeline = deformed[i] ? deforming_ : slots.y == 0 ? one_color_ : material_slots_;
    if (bound != &pipeline) {
      pipeline.bind(cmd);
      pipeline.push_descriptors(cmd, resources);
      bound = &pipeline;
    }
    gpu::GBufferPush push{};
    push.object_to_world = affine_rows(instance.object_to_world);
    push.world_to_previous_world = affine_rows(motions[i]);
    push.base_color = glm::vec4(scene.instance_color(uint32_t(i)), instance.holdout ? gpu::kHoldoutSurface : gpu::kShadedSurface);
    push.field_voxel = field_voxels[i];
    push.first_material = slots.x;
    push.material_count = slots.y;
    push.history_bit = uint32_t(i) % gpu::kHistoryBits;
    pipeline.push_constants(cmd, push);
    vkCmdDrawIndexed(cmd, 3 * mesh.triangle_count, 1, mesh.first_index, int32_t(mesh.base_vertex), 0);
  }
  vkCmdEndRenderPass(cmd);
}

}  // namespace rtsdf
