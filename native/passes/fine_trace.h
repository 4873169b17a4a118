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
  float decay = 0.9f;           // alpha, of thin pieces' slabs (fine_trace.comp)
  int rays_per_texel = 8;
  // Each band texel is traced every `interleave`-th frame (frameless-rendering
  // style), after a first frame that traces them all: per-frame work drops
  // K-fold, convergence and recovery take K times as many frames.
  int interleave = 1;
  // The RT-only baseline: no band. Every texel of the grid is listed (the band
  // and the interleave are ignored) and its rays are long enough to cross the grid.
  bool trace_everywhere = false;
  // A still field (its geometry unchanged since its first update): after
  // the first update, only texels that may improve (a neighbour's nearest
  // triangle is closer than their own, or they have none:
  // fine_probe.comp), and after each later one only those whose trace still
  // found a closer surface, are traced again. Object fields only, and not
  // where a deforming mesh keeps its history.
  bool skip_converged = false;
  // Only the texels of bricks near the band (those a packed field stores:
  // field_brick_slots.comp) are classified and traced; the rest of the dense
  // fine SDF keeps what it held. For fields that are packed for the march;
  // off, the whole dense SDF is kept up to date (tools read it).
  bool near_surface_only = false;

  // The band in world units on a coarse grid of `coarse_voxel`: texels whose
  // coarse distance is at most this are traced.
  float band_world(float coarse_voxel) const;
};

// What the fine trace reads and writes: the coarse SDF it starts from, and
// the fine SDF with its history, trace list and indirect dispatch arguments.
struct FineTraceFields {
  const GridSpec& coarse_grid;
  const vk::Image& coarse;
  float beta_world;  // the coarse SDF's beta, in world units
  const GridSpec& fine_grid;
  const vk::Image& fine;
  const vk::Image& history;
  const vk::Buffer& trace_list;  // two counts (on turn, off it) and one packed texel per fine voxel
  const vk::Buffer& dispatch;    // the trace's indirect dispatch (x, y, z, texels traced), texels improved,
                                 // then the remeasure's indirect dispatch
  const vk::Buffer& brick_state;  // two words per brick (bricks_of the fine grid): see fine_bricks_near.comp
  const vk::Buffer& near_bricks;  // the classify's indirect dispatch (4 words), then the near bricks' indices
  const vk::Buffer& doubts;  // a count and the sign step's indirect dispatch (4 words), then the doubted texels
};

// Which update this is: `frame` picks the ray set and the interleave turn;
// `first_frame` marks a field with no history; `changed` (may be null) is the
// world region where casters changed.
struct FineTraceTurn {
  uint32_t frame;
  bool first_frame;
  const Bounds* changed;
  float surface_move;  // the most any point of the surfaces moved since the last update (kUnknownSurfaceMove: not known)
};

class FineTracePass {
 public:
  explicit FineTracePass(const vk::Context& context);
  // With turn.changed, only band texels whose rays can reach it are traced, on
  // their turn (ignored on a first frame and by trace_everywhere).
  void record(VkCommandBuffer cmd, const GpuScene::RayTargets& scene, const FineTraceFields& fields,
              const FineTraceSettings& settings, const FineTraceTurn& turn, vk::GpuTimer* timer) const;

 private:
  vk::Pipeline bricks_near_;
  vk::Pipeline classify_;
  vk::Pipeline prepare_dispatch_;
  vk::Pipeline trace_;      // the texels on their turn: rays and kept triangles
  vk::Pipeline remeasure_;  // the texels off their turn in a changing field: kept triangles alone
  vk::Pipeline probe_;      // after a still field's first update: the texels that may improve
  vk::Pipeline signs_;      // the doubted signs (shaders/fine_signs.comp)
};

}  // namespace rtsdf
