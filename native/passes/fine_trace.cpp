#include "passes/fine_trace.h"

#include <cmath>
#include <limits>
#include <random>
#include <utility>

#include "shaders/shared.h"
#include "spirv/spirv_fine_bricks_near_comp.h"
#include "spirv/spirv_fine_classify_comp.h"
#include "spirv/spirv_fine_dispatch_comp.h"
#include "spirv/spirv_fine_probe_comp.h"
#include "spirv/spirv_fine_remeasure_comp.h"
#include "spirv/spirv_fine_signs_comp.h"
#include "spirv/spirv_fine_trace_comp.h"
#include "vk/context.h"
#include "vk/timer.h"

namespace rtsdf {

namespace {

constexpr VkDescriptorType kImage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
constexpr VkDescriptorType kBuffer = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
const std::vector<VkDescriptorType> kTraceBindings = {kBuffer, kBuffer, kBuffer, kBuffer, kImage, kImage,
                                                      kImage,  kBuffer, kBuffer, kBuffer, kBuffer};

// A uniformly random rotation per frame (Shoemake's quaternion), so every
// frame casts a new stratified set of directions.
glm::vec4 frame_rotation(uint32_t frame) {
  std::mt19937 rng(0x9e3779b9u ^ (frame * 2654435761u));
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  float u1 = u(rng), u2 = 2.0f * float(M_PI) * u(rng), u3 = 2.0f * float(M_PI) * u(rng);
  float a = std::sqrt(1.0f - u1), b = std::sqrt(u1);
  return {a * std::sin(u2), a * std::cos(u2), b * std::sin(u3), b * std::cos(u3)};
}

void compute_barrier(VkCommandBuffer cmd, VkPipelineStageFlags dst_stage = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VkAccessFlags dst_access = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT) {
  vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, dst_access,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, dst_stage);
}

}  // namespace

float FineTraceSettings::band_world(float coarse_voxel) const {
  return trace_everywhere ? std::numeric_limits<float>::max() : trace_band * coarse_voxel;
}

FineTracePass::FineTracePass(const vk::Context& context)
    : bricks_near_(context, RTSDF_SPIRV(spirv_fine_bricks_near_comp), {kImage, kBuffer, kBuffer}, sizeof(gpu::FinePush)),
      classify_(context, RTSDF_SPIRV(spirv_fine_classify_comp), {kImage, kImage, kImage, kBuffer, kBuffer, kBuffer},
                sizeof(gpu::FinePush)),
      prepare_dispatch_(context, RTSDF_SPIRV(spirv_fine_dispatch_comp), {kBuffer, kBuffer}, 0),
      trace_(context, RTSDF_SPIRV(spirv_fine_trace_comp), kTraceBindings, sizeof(gpu::FinePush)),
      remeasure_(context, RTSDF_SPIRV(spirv_fine_remeasure_comp), kTraceBindings, sizeof(gpu::FinePush)),
      probe_(context, RTSDF_SPIRV(spirv_fine_probe_comp), kTraceBindings, sizeof(gpu::FinePush)),
      signs_(context, RTSDF_SPIRV(spirv_fine_signs_comp), {kBuffer, kBuffer, kBuffer, kBuffer, kImage, kImage, kBuffer, kBuffer},
             sizeof(gpu::FinePush)) {}

void FineTracePass::record(VkCommandBuffer cmd, const GpuScene::RayTargets& scene, const FineTraceFields& fields,
                           const FineTraceSettings& settings, const FineTraceTurn& turn, vk::GpuTimer* timer) const {
  const GridSpec &coarse_grid = fields.coarse_grid, &fine_grid = fields.fine_grid;
  const vk::Image &coarse = fields.coarse, &fine = fields.fine, &history = fields.history;
  const vk::Buffer &trace_list = fields.trace_list, &dispatch = fields.dispatch;
  const float beta_world = fields.beta_world;
  const uint32_t frame = turn.frame;
  const bool first_frame = turn.first_frame;
  const Bounds* changed = turn.changed;
  const float coarse_voxel = coarse_grid.voxel_size;
  // Added to c_t where the texel decays towards it (the paper adds nothing):
  // beta + half a coarse voxel's diagonal makes it an upper bound of the true
  // distance, so the min with traced hits converges from above.
  const float bias = beta_world + 0.5f * std::sqrt(3.0f) * coarse_voxel;
  const glm::vec3 extent = glm::vec3(fine_grid.dims) * fine_grid.voxel_size;
  gpu::FinePush push{};
  push.rotation = frame_rotation(frame);
  push.fine_dims = glm::ivec4(fine_grid.dims, settings.rays_per_texel);
  push.fine_grid = glm::vec4(fine_grid.origin, fine_grid.voxel_size);
  push.coarse_dims = glm::ivec4(coarse_grid.dims, first_frame ? 1 : 0);
  push.coarse_grid = glm::vec4(coarse_grid.origin, coarse_voxel);
  // Rays need only reach past the band: a hit farther than band + the upper
  // bound cannot lower any value the texel can hold.
  const float band = settings.band_world(coarse_voxel);
  const float ray_length = settings.trace_everywhere
                               ? glm::length(extent)
                               : std::min(glm::length(extent), (settings.trace_band + 2.0f) * coarse_voxel + bias);
  push.params = glm::vec4(settings.decay, band, bias, ray_length);
  push.schedule = glm::uvec4(uint32_t(settings.trace_everywhere ? 1 : settings.interleave), frame, 0u, 0u);
  uint32_t flags = (settings.skip_converged ? gpu::kFineStill : 0u) |
                   (settings.near_surface_only && !settings.trace_everywhere ? gpu::kFineNearSurfaceOnly : 0u);
  if (changed && !first_frame && !settings.trace_everywhere) {
    // The texels whose centres lie within a ray's reach (and a voxel) of the change.
    const glm::vec3 reach(ray_length + fine_grid.voxel_size);
    const glm::vec3 lo = glm::ceil((changed->lo - reach - fine_grid.origin) / fine_grid.voxel_size - 0.5f);
    const glm::vec3 hi = glm::floor((changed->hi + reach - fine_grid.origin) / fine_grid.voxel_size - 0.5f);
    const glm::vec3 top(fine_grid.dims - 1);
    glm::ivec3 first(1), last(0);  // none
    if (!changed->is_empty() && !glm::any(glm::greaterThan(lo, top)) && !glm::any(glm::lessThan(hi, glm::vec3(0.0f))))
      first = glm::ivec3(glm::max(lo, glm::vec3(0.0f))), last = glm::ivec3(glm::min(hi, top));
    auto pack = [](glm::ivec3 v) { return uint32_t(v.x) | uint32_t(v.y) << gpu::kSeedBits | uint32_t(v.z) << (2 * gpu::kSeedBits); };
    push.schedule.z = pack(first);
    push.schedule.w = pack(last);
    flags |= gpu::kFineFocused;
  }
  push.state = glm::vec4(beta_world, float(flags), turn.surface_move, 0.0f);

  vkCmdFillBuffer(cmd, trace_list.handle(), 0, 2 * sizeof(uint32_t), 0u);
  const uint32_t no_doubts[4] = {0u, 0u, 1u, 1u};  // (a count, then a dispatch of 0 x 1 x 1 groups)
  vkCmdUpdateBuffer(cmd, fields.doubts.handle(), 0, sizeof no_doubts, no_doubts);
  // The bricks near the band, listed, then a work group per listed brick
  // classifies its texels: lavapipe spends as long on an invocation that
  // returns at once as on a few loads, and most of a grid is far from its
  // surfaces (a deforming character: 14 ms of each frame's update, before).
  if (first_frame) vkCmdFillBuffer(cmd, fields.brick_state.handle(), 0, VK_WHOLE_SIZE, 0u);
  vk::clear_indirect_dispatch(cmd, fields.near_bricks);
  compute_barrier(cmd);
  bricks_near_.bind(cmd);
  bricks_near_.push_descriptors(cmd, {vk::Resource::storage_image(coarse), vk::Resource::storage_buffer(fields.brick_state),
                                      vk::Resource::storage_buffer(fields.near_bricks)});
  bricks_near_.push_constants(cmd, push);
  const glm::ivec3 bricks = bricks_of(fine_grid.dims);
  vkCmdDispatch(cmd, vk::group_count(bricks.x * bricks.y * bricks.z, 64), 1, 1);
  compute_barrier(cmd, VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                  VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  classify_.bind(cmd);
  classify_.push_descriptors(cmd, {vk::Resource::storage_image(coarse), vk::Resource::storage_image(fine),
                                   vk::Resource::storage_image(history), vk::Resource::storage_buffer(trace_list),
                                   vk::Resource::storage_buffer(fields.brick_state),
                                   vk::Resource::storage_buffer(fields.near_bricks)});
  classify_.push_constants(cmd, push);
  vkCmdDispatchIndirect(cmd, fields.near_bricks.handle(), 0);
  if (timer) timer->mark(cmd, "fine classify");

  compute_barrier(cmd);
  prepare_dispatch_.bind(cmd);
  prepare_dispatch_.push_descriptors(cmd, {vk::Resource::storage_buffer(trace_list), vk::Resource::storage_buffer(dispatch)});
  vkCmdDispatch(cmd, 1, 1, 1);
  compute_barrier(cmd, VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                  VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);

  // The texels on their turn, then those measured again off it: each texel
  // is listed once, so the two write apart (their reads of neighbours'
  // history are the same benign race as within one dispatch).
  auto dispatch_over_list = [&](const vk::Pipeline& pipeline, VkDeviceSize offset) {
    pipeline.bind(cmd);
    pipeline.push_descriptors(cmd, {vk::Resource::storage_buffer(scene.top_nodes),
                                    vk::Resource::storage_buffer(scene.instances),
                                    vk::Resource::storage_buffer(scene.bottom_nodes),
                                    vk::Resource::storage_buffer(scene.triangles), vk::Resource::storage_image(coarse),
                                    vk::Resource::storage_image(fine), vk::Resource::storage_image(history),
                                    vk::Resource::storage_buffer(trace_list),
                                    vk::Resource::storage_buffer(scene.winding_dipoles),
                                    vk::Resource::storage_buffer(dispatch), vk::Resource::storage_buffer(fields.doubts)});
    pipeline.push_constants(cmd, push);
    vkCmdDispatchIndirect(cmd, dispatch.handle(), offset);
  };
  dispatch_over_list(trace_, 0);
  dispatch_over_list(remeasure_, 5 * sizeof(uint32_t));
  compute_barrier(cmd, VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                  VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  signs_.bind(cmd);
  signs_.push_descriptors(cmd, {vk::Resource::storage_buffer(scene.top_nodes), vk::Resource::storage_buffer(scene.instances),
                                vk::Resource::storage_buffer(scene.bottom_nodes),
                                vk::Resource::storage_buffer(scene.triangles), vk::Resource::storage_image(fine),
                                vk::Resource::storage_image(history), vk::Resource::storage_buffer(fields.doubts),
                                vk::Resource::storage_buffer(scene.winding_dipoles)});
  signs_.push_constants(cmd, push);
  vkCmdDispatchIndirect(cmd, fields.doubts.handle(), sizeof(uint32_t));
  // A still field's first update: which texels the next update's rays may improve.
  if (settings.skip_converged && first_frame && !settings.trace_everywhere) {
    compute_barrier(cmd);
    dispatch_over_list(probe_, 0);
  }
  if (timer) timer->mark(cmd, "fine trace");
}

}  // namespace rtsdf
