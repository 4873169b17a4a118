#pragma once
// Stage 1 of RTSDF: the coarse SDF, voxelize -> jump flood -> distance - beta.
// The result stays on the device (distance()) for the later stages.
#include <optional>
#include <vector>

#include "grid.h"
#include "gpu_scene.h"
#include "passes/jump_flood.h"
#include "passes/voxelize.h"

namespace rtsdf {

struct CoarseSdfSettings {
  int coarse_resolution = 64;  // voxels on the longest axis
  float beta = 0.5f;           // bias subtracted from the distance, in coarse voxels
};

struct CoarseSdfTimings {
  double voxelize_ms = 0.0;
  double jump_flood_ms = 0.0;     // all flood passes plus the distance conversion
  std::vector<double> pass_ms;    // each flood pass, in order
  double gpu_total_ms = 0.0;
};

class CoarseSdf {
 public:
  explicit CoarseSdf(const vk::Context& context);

  // Builds the coarse SDF of `scene` on `grid` (usually fit_grid(scene.bounds(), ...)).
  // Throws rtsdf::Error if the grid does not fit in device memory.
  void build(const GpuScene& scene, const GridSpec& grid, float beta_voxels);

  const GridSpec& grid() const { return grid_; }
  float beta_world() const { return beta_world_; }
  const vk::Image& distance() const { return distance_; }
  const CoarseSdfTimings& timings() const { return timings_; }

  // Read-backs for tools and tests (x fastest, then y, then z).
  std::vector<float> read_distance() const;
  std::vector<uint32_t> read_seeds() const;  // voxelization result, before flooding

 private:
  void allocate(const GridSpec& grid);

  const vk::Context& context_;
  VoxelizePass voxelize_;
  JumpFloodPass jump_flood_;
  vk::GpuTimer timer_;
  GridSpec grid_;
  float beta_world_ = 0.0f;
  vk::Image seeds_;     // voxelization output; the flood reads it and leaves it
  vk::Image flood_a_;
  vk::Image flood_b_;
  vk::Image distance_;
  CoarseSdfTimings timings_;
};

// Bytes of device memory a coarse SDF of `grid` needs.
size_t coarse_sdf_bytes(const GridSpec& grid);

}  // namespace rtsdf
