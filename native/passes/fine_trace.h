#pragma once
// Pass 2: the fine SDF. Classify fine texels against the coarse SDF, list the
// band (c <= d), and trace rays only from listed texels (indirect dispatch).
#include "grid.h"
#include "gpu_scene.h"
#include "vk/pipeline.h"
#include "vk/timer.h"
#include "vk/resources.h"

namespace rtsdf {

struct FineTraceSettings {
  float trace_band = 2.0f;      // d, in coarse voxels
  float decay = 0.9f;           // alpha
  int rays_per_texel = 8;
  // Each band texel is traced every `interleave`-th frame (frameless-rendering
  // style), after a first frame that traces them all: per-frame work drops
  // K-fold, convergence and recovery take K times as many frames.
  int interleave = 1;
  // Added to c_t where the texel decays towards it. 0 gives the paper's update;
  // the default (beta + half a coarse voxel diagonal) is an upper bound of the
  // true distance, so the min with traced hits converges from above.
  float decay_target_bias = -1.0f;  // < 0: the default
  // The RT-only baseline: no band. Every texel of the grid is listed (the band
  // and the interleave are ignored) and its rays are long enough to cross the grid.
  bool trace_everywhere = false;

  // The band in world units on a coarse grid of `coarse_voxel`: texels whose
  // coarse distance is at most this are traced.
  float band_world(float coarse_voxel) const;
};

class FineTracePass {
 public:
  explicit FineTracePass(const vk::Context& context);
  // `trace_list` holds a count and one packed texel per fine voxel; `dispatch`
  // holds the indirect arguments. `frame` picks the ray set and the interleave turn;
  // `first_frame` marks a field with no history. `changed` (may be null): the
  // world region where casters changed; only band texels whose rays can reach
  // it are traced, on their turn (ignored on a first frame and by trace_everywhere).
  void record(VkCommandBuffer cmd, const GpuScene::RayTargets& scene, const GridSpec& coarse_grid, const vk::Image& coarse,
              const GridSpec& fine_grid, const vk::Image& fine, const vk::Image& history,
              const vk::Buffer& trace_list, const vk::Buffer& dispatch, const FineTraceSettings& settings,
              float beta_world, uint32_t frame, bool first_frame, const Bounds* changed, vk::GpuTimer* timer) const;

 private:
  vk::Pipeline classify_;
  vk::Pipeline prepare_dispatch_;
  vk::Pipeline trace_;
};

}  // namespace rtsdf
