#pragma once
// Pass 3c: temporal reuse (shaders/temporal_resolve.comp). After the shading
// of the first frame after a change, the accumulation from before the change
// (history) is reprojected by the G-buffer's motion, dropped where another
// surface shows, clipped to the new frame's neighbourhood, and carried into
// the new accumulation: during playback every frame stands on the frames
// before it, not on one noisy sample.
#include "passes/gbuffer.h"
#include "shaders/shared.h"
#include "vk/pipeline.h"
#include "vk/resources.h"

namespace rtsdf {

// The accumulations it resolves: this frame's sample (its first frame after
// the change), the history from before the change, and where the result goes.
struct TemporalImages {
  const vk::Image& sample_color;
  const vk::Image& sample_passes;
  const vk::Image& history_color;
  const vk::Image& history_passes;
  const vk::Image& resolved_color;
  const vk::Image& resolved_passes;
};

class TemporalPass {
 public:
  explicit TemporalPass(const vk::Context& context);
  void record(VkCommandBuffer cmd, const GBufferPass& gbuffer, const TemporalImages& images, const vk::Buffer& frame,
              const vk::Buffer& lights, const gpu::TemporalPush& push) const;

 private:
  vk::Pipeline pipeline_;
};

}  // namespace rtsdf
