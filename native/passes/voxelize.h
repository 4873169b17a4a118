#pragma once
// Pass 1a: voxelization. Every voxel that a triangle passes through becomes a
// seed holding its own packed index; the rest hold kNoSeed. Triangles are
// rasterized along their dominant axis; those spanning under 2 voxels per axis
// are splatted by a compute shader instead (cheaper than a raster setup).
#include <memory>
#include <vector>

#include "grid.h"
#include "gpu_scene.h"
#include "vk/pipeline.h"

namespace rtsdf {

// A mesh of the scene placed in the grid's space.
struct VoxelizeItem {
  uint32_t mesh;
  glm::mat4 object_to_grid_space;  // the world's, for a world grid; the identity for a mesh's own grid
};

class VoxelizePass {
 public:
  explicit VoxelizePass(const vk::Context& context);
  // Voxelizes `items` into `seeds`, an r32ui storage image of the grid's dims in GENERAL layout.
  void record(VkCommandBuffer cmd, const GpuScene& scene, const GridSpec& grid, const vk::Image& seeds,
              const std::vector<VoxelizeItem>& items);

 private:
  const vk::Context& context_;
  vk::Pipeline pipeline_;
  vk::Pipeline splat_;
  std::unique_ptr<vk::Framebuffer> framebuffer_;
  uint32_t framebuffer_edge_ = 0;
};

}  // namespace rtsdf
