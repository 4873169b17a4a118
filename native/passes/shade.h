#pragma once
// Pass 3b: shading with SDF soft shadows (see shaders/shade.comp), averaged
// into the Combined and Depth/Shadow accumulation images.
#include "grid.h"
#include "shaders/shared.h"
#include "passes/gbuffer.h"
#include "vk/pipeline.h"
#include "vk/resources.h"

namespace rtsdf {

class ShadePass {
 public:
  explicit ShadePass(const vk::Context& context);
  void record(VkCommandBuffer cmd, const GBufferPass& gbuffer, const vk::Image& fine, const vk::Buffer& lights,
              const vk::Buffer& frame, const vk::Image& accum_color, const vk::Image& accum_passes,
              const gpu::ShadePush& push) const;

 private:
  vk::Pipeline pipeline_;
};

}  // namespace rtsdf
