#pragma once
// Pass 3a: the raster G-buffer from the camera: world position (w = covered),
// face normal, base colour (its instance's, or per face from its material
// slots and their images) and motion since the last frame per pixel, for
// the shading and temporal passes to read.
#include <memory>
#include <vector>

#include "gpu_scene.h"
#include "vk/pipeline.h"
#include "vk/resources.h"

namespace rtsdf {

class GBufferPass {
 public:
  explicit GBufferPass(const vk::Context& context);
  // (Re)allocates the targets for a width x height image.
  void resize(int width, int height);
  // `frame` holds one gpu::FrameData; `field_voxels`, per instance, the
  // world voxel size of the field holding it (0: in none), which the
  // shading's receiver offsets are measured in. `previous_transforms`, per
  // instance, its object_to_world in the last frame (for motion).
  void record(VkCommandBuffer cmd, const GpuScene& scene, const vk::Buffer& frame,
              const std::vector<float>& field_voxels, const std::vector<glm::mat4>& previous_transforms) const;

  const vk::Image& position() const { return position_; }
  const vk::Image& normal() const { return normal_; }
  const vk::Image& albedo() const { return albedo_; }
  const vk::Image& motion() const { return motion_; }

 private:
  const vk::Context& context_;
  // Instances of one plain colour, and those whose material slots are read per vertex.
  vk::Pipeline one_color_, material_slots_;
  int width_ = 0, height_ = 0;
  vk::Image position_, normal_, albedo_, motion_, depth_;
  std::unique_ptr<vk::Framebuffer> framebuffer_;
};

}  // namespace rtsdf
