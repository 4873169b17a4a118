#pragma once
// Pass 1a: voxelization. Every voxel that a triangle passes through becomes a
// seed holding its own packed index; the rest hold kNoSeed. Triangles are
// rasterized along their dominant axis; those spanning under 2 voxels per axis
// are splatted by a compute shader instead (cheaper than a raster setup).
#include <memory>

#include "grid.h"
#include "gpu_scene.h"
#include "vk/pipeline.h"

namespace rtsdf {

class VoxelizePass {
 public:
  explicit VoxelizePass(const vk::Context& context);
  // `seeds` must be an r32ui storage image of the grid's dims in GENERAL layout.
  void record(VkCommandBuffer cmd, const GpuScene& scene, const GridSpec& grid, const vk::Image& seeds);

 private:
  const vk::Context& context_;
  vk::Pipeline pipeline_;
  vk::Pipeline splat_;
  std::unique_ptr<vk::Framebuffer> framebuffer_;
  uint32_t framebuffer_edge_ = 0;
};

}  // namespace rtsdf
