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

class TemporalPass {
 public:
  explicit TemporalPass(const vk::Context& context);
  // Reads this frame's sample (accum_*) and the history (history_*), writes
  // the resolved accumulation into resolved_*.
  void record(VkCommandBuffer cmd, const GBufferPass& gbuffer, const vk::Image& accum_color,
              const vk::Image& accum_passes, const vk::Image& history_color, const vk::Image& history_passes,
              const vk::Buffer& frame, const vk::Buffer& lights, const vk::Image& resolved_color,
              const vk::Image& resolved_passes, const gpu::TemporalPush& push) const;

 private:
  vk::Pipeline pipeline_;
};

}  // namespace rtsdf
