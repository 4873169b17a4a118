#pragma once
// Pass 3c: temporal reuse (shaders/temporal_keep.comp, temporal_resolve.comp).
// Before the shading of the first frame after a change, the pixels whose
// history stands whatever they would sample (still, away from what moved)
// keep it, and are not shaded. After the shading
// of the first frame after a change, the accumulation from before the change
// (history) is reprojected by the G-buffer's motion, dropped where another
// surface shows, clipped to the new frame's neighbourhood, and carried into
// the new accumulation: during playback every frame stands on the frames
// before it, not on one noisy sample.
#include "passes/gbuffer.h"
#include "screen_region.h"
#include "shaders/shared.h"
#include "vk/pipeline.h"
#include "vk/resources.h"

namespace rtsdf {

// The accumulations it resolves: this frame's sample (its first frame after
// the change), the history from before the change, and where the result goes.
// The lists of tiles where a keep pass left pixels to shade
// (shaders/kept_tiles.glsl.h): the pixel tiles' and the quad groups'
// indirect dispatches, at these byte offsets of `buffer`.
struct KeptTiles {
  const vk::Buffer& buffer;
  VkDeviceSize pixel_dispatch;
  VkDeviceSize quad_dispatch;
};

// Each pixel's running means over its samples, and their second moments:
// the images of one accumulation, which change roles together.
struct Accumulation {
  vk::Image color;    // rgb = Combined, a = coverage
  vk::Image passes;   // x = nearest depth, y = shadow, z = samples in the pixel's mean, w = farthest depth
  vk::Image moments;  // the samples' second moments (shaders/sample_moments.glsl.h)
};

// The accumulations the temporal passes read and write: this frame's
// sample, the history reprojected from, and the resolved one (the sample's
// moments are the shading's alone).
struct TemporalImages {
  const Accumulation& sample;
  const Accumulation& history;
  const Accumulation& resolved;
};

class TemporalPass {
 public:
  explicit TemporalPass(const vk::Context& context);
  // (Re)allocates the tile list for a width x height image.
  void resize(glm::ivec2 size);
  // Where every pixel a step would not keep lies in the tiles `unsettled`:
  // the tiles the keep pass tests, those and the neighbours the resolve
  // reads of their kept pixels (the shading reads no mark of the keep pass
  // outside the tiles it lists, shade_inputs.glsl.h's left_unshaded).
  TileMask keep_region(const TileMask& unsettled) const;
  // ... and the rectangle holding the pixels whose G-buffer the step reads:
  // those tiles, the quad groups that share samples with them, and the
  // resolve's neighbours.
  PixelRect drawn_region(const TileMask& unsettled) const;
  // Before the shading (shaders/temporal_keep.comp), over the tiles `region` (from
  // keep_region): where history stands whatever the new sample, it is
  // resolved (images.resolved_*) and becomes the sample (images.sample_*),
  // marked for the shading and the resolve to skip (gpu::kKeptSample). The
  // tiles holding pixels it did not keep are listed. Outside the region,
  // history is copied as it was into the resolved images and the sample's
  // colour (the sample's passes there are left: nothing reads them).
  void record_keep(VkCommandBuffer cmd, const GBufferPass& gbuffer, const TemporalImages& images,
                   const vk::Buffer& frame, const vk::Buffer& lights, gpu::TemporalPush push,
                   const TileMask& region) const;
  // Adaptive sampling, after a frame (shaders/temporal_converged.comp): of
  // the tiles `region` (those the frame shaded: a tile left out before
  // stays so), those whose pixels' samples in `accumulation` agree within
  // push.noise_threshold have converged (their pixels counted as sampled in
  // full from then on); the others are listed for the next frame's shading
  // (kept_tiles).
  void record_converged(VkCommandBuffer cmd, const Accumulation& accumulation, const gpu::TemporalPush& push,
                        const TileMask& region) const;
  // The tiles holding the pixels the last keep pass did not keep (none if
  // it kept them all), or the last converged test found short of samples;
  // read once its commands have run.
  TileMask unsettled_tiles() const;
  // The share of the image the last keep pass marked short of history
  // (gpu::kShortHistorySample: their exact rays are more).
  double short_history_share() const;
  // After it (shaders/temporal_resolve.comp). `after_keep`: over the tiles
  // the keep pass listed alone, with the History it handed on (the
  // pipeline with kListedTiles); otherwise over every pixel.
  void record(VkCommandBuffer cmd, const GBufferPass& gbuffer, const TemporalImages& images, const vk::Buffer& frame,
              const vk::Buffer& lights, const gpu::TemporalPush& push, bool after_keep) const;
  // The lists of tiles where the last keep pass or converged test left
  // pixels to shade (for ShadeInputs::kept_tiles).
  KeptTiles kept_tiles() const;

 private:
  const vk::Context& context_;
  vk::Pipeline keep_;
  vk::Pipeline quad_groups_;  // (shaders/temporal_quad_groups.comp)
  vk::Pipeline resolve_;         // (finds each pixel's history)
  vk::Pipeline resolve_listed_;  // (over the keep pass's list, taking the History it handed on)
  vk::Pipeline converged_;       // (shaders/temporal_converged.comp)
  // No tile listed in either list.
  void clear_lists(VkCommandBuffer cmd) const;
  // After the pixel tiles are listed: their flags read back to the host (and
  // the keep pass's count of pixels short of history), and the quad groups
  // listed beside them (shaders/temporal_quad_groups.comp).
  void list_quad_groups(VkCommandBuffer cmd, const gpu::TemporalPush& push, bool short_history_count) const;

  glm::ivec2 size_{0};
  vk::Buffer tiles_;  // see gpu::kTemporalTile
  vk::Buffer unsettled_;  // the listed pixel tiles' flags (host-visible: the next step's or frame's region)
  vk::Buffer keep_tiles_;  // the tiles the keep pass runs over (host-visible: written as it is recorded)
  vk::Buffer tested_tiles_;  // ... and the converged test (likewise)
};

}  // namespace rtsdf
