#pragma once
// Pass 3a: the raster G-buffer from the camera: world position (w = covered),
// face normal, base colour (its instance's, or per face from its material
// slots and their images) and motion since the last frame per pixel, for
// the shading and temporal passes to read.
#include <memory>
#include <vector>

#include "gpu_scene.h"
#include "screen_region.h"
#include "vk/pipeline.h"
#include "vk/resources.h"

namespace rtsdf {

// Where each instance's points were in the last frame, from where they are
// now: per instance, world to last frame's world, from its object_to_world
// then (`before`) and now (the identity where it stayed). A transform that
// flattens the instance (kDegenerateScale, as the fields judge it) has no
// inverse: its motion is its origin's. Made once per change, not per frame.
std::vector<glm::mat4> world_motions(const std::vector<glm::mat4>& before, const std::vector<glm::mat4>& now);

class GBufferPass {
 public:
  explicit GBufferPass(const vk::Context& context);
  // (Re)allocates the targets for a width x height image.
  void resize(int width, int height);
  // `frame` holds one gpu::FrameData; `field_voxels`, per instance, the
  // world voxel size of the field holding it (0: in none), which the
  // shading's receiver offsets are measured in. `motions`, per instance,
  // where its points were in the last frame (world_motions); `deformed`, per
  // instance, whether its mesh deformed since then: each vertex's motion
  // then starts from where GpuScene::previous_positions() has it. Draws the
  // pixels of `region` alone (a playback step reads no others:
  // TemporalPass::drawn_region); the rest keep what they held.
  void record(VkCommandBuffer cmd, const GpuScene& scene, const vk::Buffer& frame,
              const std::vector<float>& field_voxels, const std::vector<glm::mat4>& motions,
              const std::vector<uint8_t>& deformed, const PixelRect& region) const;

  const vk::Image& position() const { return position_; }
  const vk::Image& normal() const { return normal_; }
  const vk::Image& albedo() const { return albedo_; }
  const vk::Image& motion() const { return motion_; }

 private:
  const vk::Context& context_;
  // Instances of one plain colour, those whose material slots are read per
  // vertex, and those whose mesh deformed since the last frame (slots read,
  // and each vertex's last position: a varying more, which lavapipe sets up
  // for every triangle, so the rigid ones go without).
  vk::Pipeline one_color_, material_slots_, deforming_;
  int width_ = 0, height_ = 0;
  vk::Image position_, normal_, albedo_, motion_, depth_;
  std::unique_ptr<vk::Framebuffer> framebuffer_;
};

}  // namespace rtsdf
