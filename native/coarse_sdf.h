#pragma once
// Stage 1 of RTSDF: the coarse SDF, voxelize -> distance transform (the
// paper's jump flood for the whole scene's field, the exact transform for a
// mesh's own) -> distance - beta. The result stays on the device
// (distance()) for the later stages.
#include <memory>
#include <optional>
#include <vector>

#include "grid.h"
#include "gpu_scene.h"
#include "passes/exact_distance.h"
#include "passes/jump_flood.h"
#include "passes/voxelize.h"

namespace rtsdf {

struct CoarseSdfSettings {
  int coarse_resolution = 64;  // voxels on the longest axis
  float beta = 0.5f;           // bias subtracted from the distance, in coarse voxels
};

struct CoarseSdfTimings {
  double voxelize_ms = 0.0;
  double jump_flood_ms = 0.0;     // all flood passes plus the distance conversion (the whole scene's field)
  std::vector<double> pass_ms;    // each flood pass, in order
  double exact_distance_ms = 0.0; // the exact transform's three passes (a mesh's field)
  double gpu_total_ms = 0.0;
};

// Bytes of device memory a coarse SDF of `grid` needs.
size_t coarse_sdf_bytes(const GridSpec& grid);

// The passes a coarse SDF is built with; fields may share one (its pipelines are the costly part).
struct CoarsePasses {
  explicit CoarsePasses(const vk::Context& context) : voxelize(context), jump_flood(context), exact_distance(context) {}
  VoxelizePass voxelize;
  JumpFloodPass jump_flood;
  ExactDistancePass exact_distance;
};

class CoarseSdf {
 public:
  // `passes` null: passes of its own.
  explicit CoarseSdf(const vk::Context& context, std::shared_ptr<CoarsePasses> passes = nullptr);

  // Builds the coarse SDF of the scene's shadow casters on `grid` in world
  // space (usually fit_grid(scene.bounds(), ...)), by the paper's jump flood.
  // Throws rtsdf::Error if the grid does not fit in device memory.
  void build(const GpuScene& scene, const GridSpec& grid, float beta_voxels);
  // Builds the coarse SDF of one mesh alone on `grid` in the mesh's own
  // space, by the exact distance transform: a deforming mesh's field is
  // built every frame, and the flood's 27 reads a voxel in each of its
  // passes were most of that build.
  void build_mesh(const GpuScene& scene, uint32_t mesh, const GridSpec& grid, float beta_voxels);
  // Device memory of the grid's images.
  size_t bytes() const { return coarse_sdf_bytes(grid_); }
  // Frees the images (a field packed for the march needs them no more);
  // the next build allocates them again.
  void release();

  const GridSpec& grid() const { return grid_; }
  float beta_world() const { return beta_world_; }
  const vk::Image& distance() const { return distance_; }
  const CoarseSdfTimings& timings() const { return timings_; }

  // Read-backs for tools and tests (x fastest, then y, then z).
  std::vector<float> read_distance() const;
  std::vector<uint32_t> read_seeds() const;  // voxelization result, before flooding

 private:
  void allocate(const GridSpec& grid);
  enum class Transform { JumpFlood, Exact };
  void build(const GpuScene& scene, const GridSpec& grid, float beta_voxels, const std::vector<VoxelizeItem>& items,
             Transform transform);

  const vk::Context& context_;
  std::shared_ptr<CoarsePasses> passes_;
  vk::GpuTimer timer_;
  GridSpec grid_;
  float beta_world_ = 0.0f;
  vk::Image seeds_;     // voxelization output; the flood reads it and leaves it
  vk::Image flood_a_;
  vk::Image flood_b_;
  vk::Image distance_;
  CoarseSdfTimings timings_;
};

}  // namespace rtsdf
