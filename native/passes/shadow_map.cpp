#include "passes/shadow_map.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>

#include "error.h"
#include "spirv/spirv_shadow_map_frag.h"
#include "spirv/spirv_shadow_map_vert.h"
#include "vk/context.h"

namespace rtsdf {

namespace {

constexpr VkFormat kMoments = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kDepth = VK_FORMAT_D32_SFLOAT;
constexpr VkDescriptorType kBuffer = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;

std::array<glm::vec3, 8> corners(const Bounds& b) {
  std::array<glm::vec3, 8> out;
  for (int i = 0; i < 8; ++i)
    out[i] = {i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z};
  return out;
}

// Smallest and largest dot(axis, p) over the box.
glm::vec2 extent_along(const Bounds& b, glm::vec3 axis) {
  glm::vec2 range(1e30f, -1e30f);
  for (const glm::vec3& c : corners(b)) range = {std::min(range.x, glm::dot(axis, c)), std::max(range.y, glm::dot(axis, c))};
  return range;
}

float distance_to_box(glm::vec3 p, const Bounds& b) { return glm::length(glm::max(glm::max(b.lo - p, p - b.hi), 0.0f)); }

// Two unit vectors completing `forward` to a basis (fixed for a given
// forward, so a sun's texel grid does not turn with the camera).
void basis(glm::vec3 forward, glm::vec3& right, glm::vec3& up) {
  const glm::vec3 hint = std::abs(forward.z) < 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
  right = glm::normalize(glm::cross(forward, hint));
  up = glm::cross(right, forward);
}

glm::mat4 from_rows(glm::vec4 r0, glm::vec4 r1, glm::vec4 r2, glm::vec4 r3) {
  return glm::transpose(glm::mat4(r0, r1, r2, r3));
}

// What the views are fitted to.
struct Fit {
  Bounds casters;           // bounds of the shadow casters
  Bounds everything;        // bounds of all geometry (the receivers too)
  float reference_distance; // typical occluder-to-receiver distance: half the casters' diagonal
  int size;                 // texels per tile side
  float filter_radius;      // texels: the lookup's fixed filter (0: penumbra-wide)
};

// The texels a tile keeps clear of its border when a lookup picks it: the
// filter's reach, a fixed one's or that of a penumbra of `penumbra_world`
// (the light's penumbra at the reference distance, twice over for the
// farther receivers) where a texel is `texel_world`; up to kMaxFilterRadius and an eighth of the tile.
void set_reach(gpu::ShadowTile& tile, const Fit& fit, float penumbra_world, float texel_world) {
  const float wanted = fit.filter_radius > 0.0f ? fit.filter_radius : 2.0f * penumbra_world / texel_world;
  const float reach = std::min({wanted, ShadowMapPass::kMaxFilterRadius, fit.size / 8.0f});
  tile.atlas.z = int(std::ceil(reach)) + 1;
}

// A perspective view from a local light's position along `forward`, its
// square frustum `tan_half` wide (at unit depth) before the filter's margin is added.
gpu::ShadowTile perspective_view(const Fit& fit, const Light& light, glm::vec3 forward, float tan_half) {
  gpu::ShadowTile tile{};
  const glm::vec3 position = light.position;
  float far = 0.0f;
  for (const glm::vec3& c : corners(fit.everything)) far = std::max(far, glm::dot(forward, c - position));
  far *= 1.01f;
  const float near = std::max(0.95f * distance_to_box(position, fit.casters), 1e-4f * far);
  if (!(far > near)) far = near * 2.0f;
  const float occluder = std::max(glm::length(0.5f * (fit.casters.lo + fit.casters.hi) - position), 1e-4f);
  const float receiver_depth = occluder + fit.reference_distance;
  set_reach(tile, fit, light.radius * fit.reference_distance / occluder,
            2.0f * tan_half * receiver_depth / float(fit.size));
  // Widen the frustum so the margin the filter needs lies outside the cone.
  const float tan_wide = tan_half * float(fit.size) / float(std::max(fit.size - 2 * tile.atlas.z, 1));
  glm::vec3 right, up;
  basis(forward, right, up);
  const glm::mat4 world_to_view = glm::lookAtRH(position, position + forward, up);
  tile.world_to_clip = glm::perspectiveRH_ZO(2.0f * std::atan(tan_wide), 1.0f, near, far) * world_to_view;
  tile.depth_axis = glm::vec4(forward, -glm::dot(forward, position));
  tile.depth_range = glm::vec4(near, 1.0f / (far - near), 0.0f, 2.0f * tan_wide / float(fit.size));
  tile.light = glm::vec4(light.radius, 1.0f, 0.0f, 0.0f);
  return tile;
}

// The camera's depth range [near, far] (distances along the view axis) from
// an OpenGL-style projection, orthographic or perspective.
glm::vec2 camera_depth_range(const glm::mat4& p) {
  if (p[3][3] == 1.0f) return {(p[3][2] + 1.0f) / p[2][2], (p[3][2] - 1.0f) / p[2][2]};
  return {p[3][2] / (p[2][2] - 1.0f), p[3][2] / (p[2][2] + 1.0f)};
}

// A sun's cascades over the camera's depth range, clipped to the scene's.
std::vector<gpu::ShadowTile> sun_views(const Fit& fit, const Light& light, const glm::mat4& world_to_view,
                                       const glm::mat4& projection) {
  const glm::vec3 forward = glm::normalize(light.direction);
  glm::vec3 right, up;
  basis(forward, right, up);
  glm::vec2 depth = camera_depth_range(projection);
  glm::vec2 scene_depth(1e30f, -1e30f);  // the scene's own range in view depth
  for (const glm::vec3& c : corners(fit.everything)) {
    const float d = -(world_to_view * glm::vec4(c, 1.0f)).z;
    scene_depth = {std::min(scene_depth.x, d), std::max(scene_depth.y, d)};
  }
  const float near = std::max(depth.x, scene_depth.x), far = std::min(depth.y, scene_depth.y);
  if (!(far > near)) return {};  // nothing in view
  // The practical split scheme (logarithmic blended with uniform). An
  // orthographic camera's texel density does not fall with depth: uniform.
  const bool orthographic = projection[3][3] == 1.0f;
  const float lambda = orthographic || near <= 0.0f ? 0.0f : ShadowMapPass::kSplitLambda;
  std::vector<float> split(ShadowMapPass::kCascades + 1);
  for (int i = 0; i <= ShadowMapPass::kCascades; ++i) {
    const float s = float(i) / ShadowMapPass::kCascades;
    split[i] = i == 0 ? near : i == ShadowMapPass::kCascades ? far
             : lambda * near * std::pow(far / near, s) + (1.0f - lambda) * (near + (far - near) * s);
  }

  const glm::mat4 clip_to_world = glm::inverse(projection * world_to_view);
  auto ndc_z = [&](float d) {
    const glm::vec4 clip = projection * glm::vec4(0.0f, 0.0f, -d, 1.0f);
    return clip.z / clip.w;
  };
  const float tan_light = std::tan(0.5f * std::min(light.sun_angle, 0.99f * float(M_PI)));
  const float penumbra_world = fit.reference_distance * tan_light;
  const glm::vec2 caster_range = extent_along(fit.casters, forward), scene_range = extent_along(fit.everything, forward);
  std::vector<gpu::ShadowTile> views;
  for (int i = 0; i < ShadowMapPass::kCascades; ++i) {
    std::array<glm::vec3, 8> slice;
    for (int k = 0; k < 8; ++k) {
      const glm::vec4 p = clip_to_world * glm::vec4(k & 1 ? 1.0f : -1.0f, k & 2 ? 1.0f : -1.0f,
                                                    ndc_z(k & 4 ? split[i + 1] : split[i]), 1.0f);
      slice[k] = glm::vec3(p) / p.w;
    }
    glm::vec3 center(0.0f);
    for (const glm::vec3& c : slice) center += c / 8.0f;
    float radius = 0.0f;
    for (const glm::vec3& c : slice) radius = std::max(radius, glm::length(c - center));
    // A bounding sphere keeps the tile's size as the camera turns; rounded up
    // (to 1/64 of its power of two) it keeps it as the camera moves slightly too.
    const float quantum = std::exp2(std::floor(std::log2(std::max(radius, 1e-6f)))) / 64.0f;
    radius = std::ceil(radius / quantum) * quantum;
    // Room for the filter's margin (and two texels) around the slice.
    const float half = radius + 2.0f * penumbra_world + 4.0f * radius / float(fit.size);
    const float texel = 2.0f * half / float(fit.size);
    gpu::ShadowTile tile{};
    set_reach(tile, fit, penumbra_world, texel);
    // Whole-texel steps of the tile's centre: a moving camera does not shift the texel grid.
    const float cx = std::floor(glm::dot(right, center) / texel) * texel;
    const float cy = std::floor(glm::dot(up, center) / texel) * texel;
    // Depth: from the casters nearest the sun to the far side of the slice.
    float z_near = caster_range.x, z_far = std::min(glm::dot(forward, center) + half, scene_range.y);
    const float pad = 0.01f * std::max(z_far - z_near, 1e-3f);
    z_near -= pad;
    z_far = std::max(z_far + pad, z_near + 2.0f * pad);
    const float inv_range = 1.0f / (z_far - z_near);
    tile.world_to_clip = from_rows(glm::vec4(right / half, -cx / half), glm::vec4(up / half, -cy / half),
                                   glm::vec4(forward * inv_range, -z_near * inv_range), glm::vec4(0, 0, 0, 1));
    tile.depth_axis = glm::vec4(forward, 0.0f);
    tile.depth_range = glm::vec4(z_near, inv_range, texel, 0.0f);
    tile.light = glm::vec4(tan_light, 0.0f, 0.0f, 0.0f);
    views.push_back(tile);
  }
  return views;
}

// A spot up to 120 degrees wide is one view; wider ones (and point and area
// lights) a cube.
bool one_view(const Light& light) { return light.type == LightType::Spot && light.spot_size <= 2.0f * float(M_PI) / 3.0f; }

// Tiles a light gets at most.
long tile_count(const Light& light) { return light.type == LightType::Sun ? ShadowMapPass::kCascades : one_view(light) ? 1 : 6; }

std::vector<gpu::ShadowTile> light_views(const Fit& fit, const Light& light, const glm::mat4& world_to_view,
                                         const glm::mat4& projection) {
  if (light.type == LightType::Sun) return sun_views(fit, light, world_to_view, projection);
  if (one_view(light)) {
    const glm::vec3 forward = glm::length(light.direction) > 0.0f ? glm::normalize(light.direction) : glm::vec3(0, 0, -1);
    return {perspective_view(fit, light, forward, std::tan(0.5f * light.spot_size))};
  }
  std::vector<gpu::ShadowTile> faces;
  for (int axis = 0; axis < 6; ++axis) {
    glm::vec3 forward(0.0f);
    forward[axis / 2] = axis % 2 ? -1.0f : 1.0f;
    faces.push_back(perspective_view(fit, light, forward, 1.0f));
  }
  return faces;
}

}  // namespace

ShadowMapPass::ShadowMapPass(const vk::Context& context)
    : context_(context),
      raster_(context, RTSDF_SPIRV(spirv_shadow_map_vert), RTSDF_SPIRV(spirv_shadow_map_frag),
              {kBuffer, kBuffer, kBuffer}, sizeof(gpu::ShadowMapPush), vk::RenderTargets{{kMoments}, kDepth}) {}

void ShadowMapPass::setup(const GpuScene& scene, const std::vector<Light>& lights, const glm::mat4& world_to_view,
                          const glm::mat4& projection, int size, float filter_radius) {
  if (size < 64 || size > 4096) throw Error("shadow_map_size must be 64 to 4096");
  tile_data_.clear();
  std::vector<gpu::ShadowLightTiles> ranges(std::max<size_t>(lights.size(), 1), gpu::ShadowLightTiles{});
  std::vector<std::vector<gpu::ShadowTile>> views(lights.size());
  if (!scene.shadow_casters().empty()) {
    // More tiles than the atlas (or the device's largest image) holds at
    // `size`: smaller tiles.
    long tiles = 0;
    for (const Light& light : lights) tiles += tile_count(light);
    const long side = long(std::ceil(std::sqrt(double(tiles))));
    const long largest = std::min(context_.limits().maxImageDimension2D,
                                  std::min(context_.limits().maxFramebufferWidth, context_.limits().maxFramebufferHeight));
    while (size > 16 && (tiles * size * size > kMaxAtlasTexels || side * size > largest)) size /= 2;
    const Fit fit{scene.bounds(), scene.scene().world_bounds(), 0.5f * glm::length(scene.bounds().extent()), size,
                  filter_radius};
    for (size_t l = 0; l < lights.size(); ++l) views[l] = light_views(fit, lights[l], world_to_view, projection);
  }
  for (size_t l = 0; l < lights.size(); ++l) {
    ranges[l] = {uint32_t(tile_data_.size()), uint32_t(views[l].size()), 0u, 0u};
    tile_data_.insert(tile_data_.end(), views[l].begin(), views[l].end());
  }

  // Tiles in a near-square grid in one atlas.
  const int count = int(tile_data_.size());
  const int columns = count ? int(std::ceil(std::sqrt(double(count)))) : 1;
  const glm::ivec2 grid(columns, count ? (count + columns - 1) / columns : 1);
  for (int t = 0; t < count; ++t) tile_data_[t].atlas.x = (t % columns) * size, tile_data_[t].atlas.y = (t / columns) * size;
  if (size != tile_size_ || grid != atlas_tiles_ || !moments_.handle()) {
    framebuffer_.reset();
    const glm::ivec2 texels = grid * size;
    moments_ = vk::Image::plane(context_, texels.x, texels.y, kMoments,
                                VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT);
    depth_ = vk::Image::plane(context_, texels.x, texels.y, kDepth, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT);
    framebuffer_ = std::make_unique<vk::Framebuffer>(context_, raster_.render_pass(), uint32_t(texels.x),
                                                     uint32_t(texels.y),
                                                     std::vector<VkImageView>{moments_.view(), depth_.view()});
    // GENERAL from the start: shading may read the atlas before anything is rendered into it.
    vk::make_general(context_, {&moments_});
    tile_size_ = size;
    atlas_tiles_ = grid;
  }
  const VkDeviceSize tile_bytes = std::max<size_t>(count, 1) * sizeof(gpu::ShadowTile);
  if (!tiles_ || tiles_.size() < tile_bytes)
    tiles_ = vk::Buffer(context_, tile_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::Buffer::Access::HostVisible);
  if (count) std::memcpy(tiles_.mapped(), tile_data_.data(), count * sizeof(gpu::ShadowTile));
  const VkDeviceSize range_bytes = ranges.size() * sizeof(gpu::ShadowLightTiles);
  if (!light_tiles_ || light_tiles_.size() < range_bytes)
    light_tiles_ = vk::Buffer(context_, range_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::Buffer::Access::HostVisible);
  std::memcpy(light_tiles_.mapped(), ranges.data(), range_bytes);
}

void ShadowMapPass::record(VkCommandBuffer cmd, const GpuScene& scene) const {
  if (tile_data_.empty()) return;
  const glm::vec4 exponents(kPositiveExponent, kNegativeExponent, 0.0f, 0.0f);
  // Cleared to the moments of the far plane: lit wherever no caster is drawn.
  VkClearValue clears[2]{};
  const float far_positive = std::exp(kPositiveExponent), far_negative = -std::exp(-kNegativeExponent);
  clears[0].color = {{far_positive, far_positive * far_positive, far_negative, far_negative * far_negative}};
  clears[1].depthStencil = {1.0f, 0};
  const glm::ivec3 texels = moments_.dims();
  VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  begin.renderPass = raster_.render_pass();
  begin.framebuffer = framebuffer_->handle();
  begin.renderArea = {{0, 0}, {uint32_t(texels.x), uint32_t(texels.y)}};
  begin.clearValueCount = 2;
  begin.pClearValues = clears;
  vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
  raster_.bind(cmd);
  raster_.push_descriptors(cmd, {vk::Resource::storage_buffer(scene.positions()),
                                 vk::Resource::storage_buffer(scene.indices()), vk::Resource::storage_buffer(tiles_)});
  for (size_t t = 0; t < tile_data_.size(); ++t) {
    const glm::ivec4& atlas = tile_data_[t].atlas;
    VkViewport viewport{float(atlas.x), float(atlas.y), float(tile_size_), float(tile_size_), 0.0f, 1.0f};
    VkRect2D scissor{{atlas.x, atlas.y}, {uint32_t(tile_size_), uint32_t(tile_size_)}};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    for (uint32_t i : scene.shadow_casters()) {
      const Instance& instance = scene.instances()[i];
      const GpuMeshRange& mesh = scene.meshes()[instance.mesh];
      if (mesh.triangle_count == 0) continue;
      gpu::ShadowMapPush push{};
      push.object_to_world = instance.object_to_world;
      push.evsm = exponents;
      push.first_index = mesh.first_index;
      push.base_vertex = mesh.base_vertex;
      push.tile = uint32_t(t);
      raster_.push_constants(cmd, push);
      vkCmdDraw(cmd, 3 * mesh.triangle_count, 1, 0, 0);
    }
  }
  vkCmdEndRenderPass(cmd);
}

}  // namespace rtsdf
