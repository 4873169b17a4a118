#pragma once
// Stage 2 of RTSDF: the fine SDF, ray traced near surfaces and accumulated
// over frames on the device. Nothing is read back in the frame loop.
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
  explicit FineSdf(const vk::Context& context);

  // The fine grid: `fine_resolution` voxels on the longest axis over the coarse grid's bounds.
  static GridSpec fit(const GridSpec& coarse, int fine_resolution);

  // One frame: classify against `coarse` (built this frame) and trace the band
  // (with `changed`: only the band near that world region; the rest keeps
  // its values). A new grid or reset() starts accumulation afresh.
  void update(GpuScene& scene, const CoarseSdf& coarse, const GridSpec& fine_grid,
              const FineTraceSettings& settings, const Bounds* changed = nullptr);
  void reset() { frame_ = 0; }

  const GridSpec& grid() const { return grid_; }
  const vk::Image& distance() const { return distance_; }
  uint32_t frames() const { return frame_; }
  const FineFrameStats& last_frame() const { return stats_; }

  // Read-backs for tools and tests (x fastest).
  std::vector<float> read_distance() const;
  uint32_t read_traced_texels() const;  // texels in the band in the last frame

 private:
  void allocate(const GridSpec& grid);

  const vk::Context& context_;
  FineTracePass pass_;
  vk::GpuTimer timer_;
  GridSpec grid_;
  vk::Image distance_;
  vk::Image hit_counts_;
  vk::Buffer trace_list_;
  vk::Buffer dispatch_;
  uint32_t frame_ = 0;
  FineFrameStats stats_;
};

}  // namespace rtsdf
