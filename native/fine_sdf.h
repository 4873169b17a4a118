#pragma once
// Stage 2 of RTSDF: the fine SDF, ray traced near surfaces and accumulated
// over frames on the device. Nothing is read back in the frame loop.
#include <memory>
#include <vector>

#include "coarse_sdf.h"
#include "passes/fine_trace.h"

namespace rtsdf {

struct FineFrameStats {
  double classify_ms = 0.0;
  double trace_ms = 0.0;
  double total_ms() const { return classify_ms + trace_ms; }
};

class FineSdf {
 public:
  // `pass` may be shared between fields (its pipelines are the costly part); null: a pass of its own.
  explicit FineSdf(const vk::Context& context, std::shared_ptr<const FineTracePass> pass = nullptr);

  // The fine grid: `fine_resolution` voxels on the longest axis over the coarse grid's bounds.
  static GridSpec fit(const GridSpec& coarse, int fine_resolution);

  // One frame: classify against `coarse` (built this frame) and trace the band
  // (with `changed`: only the band near that world region; the rest keeps
  // its values). A new grid or reset() starts accumulation afresh.
  void update(GpuScene& scene, const CoarseSdf& coarse, const GridSpec& fine_grid,
              const FineTraceSettings& settings, const Bounds* changed = nullptr);
  // The same, tracing `rays` (one mesh in its own space: GpuScene::mesh_rays).
  // `surface_move`: the most any point of the mesh's surface moved since the
  // last update (GpuScene::mesh_move_since), where it is known: the texels of a
  // field whose geometry changes that lie farther from the surface than that
  // keep their sign without a doubt (fine_trace.glsl.h).
  void update(const GpuScene::RayTargets& rays, const CoarseSdf& coarse, const GridSpec& fine_grid,
              const FineTraceSettings& settings, const Bounds* changed = nullptr,
              float surface_move = gpu::kUnknownSurfaceMove);
  void reset() { frame_ = 0; }
  // Frees the images and lists (a field packed for the march needs them no
  // more); the next update allocates them again and starts afresh.
  void release();

  const GridSpec& grid() const { return grid_; }
  const vk::Image& distance() const { return distance_; }
  uint32_t frames() const { return frame_; }
  const FineFrameStats& last_frame() const { return stats_; }

  // Read-backs for tools and tests (x fastest).
  std::vector<float> read_distance() const;
  uint32_t read_traced_texels() const { return read_count(0); }  // texels traced in the last update (0 before any)
  // Of those, in a still field (FineTraceSettings::skip_converged), texels
  // whose rays found a surface a quarter voxel closer than their value (0
  // on a first update, and in other fields): how far from converged.
  uint32_t read_improved_texels() const { return read_count(1); }
  // Texels whose sign the last update doubted and took from the winding number (fine_signs.comp).
  uint32_t read_doubted_texels() const { return read_count(2); }
  // Device memory of the grid's images and lists.
  size_t bytes() const { return grid_.voxel_count() * kBytesPerTexel + brick_state_.size() + near_bricks_.size(); }
  static constexpr size_t kBytesPerTexel = 4 + 16 + 4 + 1;  // distance, history, trace list, doubted signs (1 in 4)

 private:
  void allocate(const GridSpec& grid);
  uint32_t read_count(int which) const;  // the last update's: 0 traced, 1 improved, 2 doubted

  const vk::Context& context_;
  std::shared_ptr<const FineTracePass> pass_;
  vk::GpuTimer timer_;
  GridSpec grid_;
  vk::Image distance_;
  vk::Image history_;
  vk::Buffer trace_list_;
  vk::Buffer dispatch_;
  vk::Buffer brick_state_;  // per brick of the grid, see fine_bricks_near.comp
  vk::Buffer doubts_;  // the texels whose sign the trace doubted (shaders/fine_signs.comp)
  static constexpr size_t kDoubtRoom = 1024;  // (entries beyond one texel in four: small grids)
  vk::Buffer near_bricks_;  // the bricks near the band, and the classify's dispatch
  vk::Buffer traced_;  // host-visible copy of the last update's counts (read_count)
  uint32_t frame_ = 0;
  FineFrameStats stats_;
};

}  // namespace rtsdf
