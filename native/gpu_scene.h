#pragma once
// The scene's geometry on the device: every mesh's positions and indices in
// two shared storage buffers, plus the instances that place them.
#include <vector>

#include "scene.h"
#include "vk/resources.h"

namespace rtsdf {

struct GpuMeshRange {
  uint32_t first_index = 0;
  uint32_t base_vertex = 0;
  uint32_t triangle_count = 0;
};

class GpuScene {
 public:
  // Validates and uploads `scene`; throws rtsdf::Error on bad input.
  GpuScene(const vk::Context& context, const Scene& scene);

  const vk::Buffer& positions() const { return positions_; }
  const vk::Buffer& indices() const { return indices_; }
  const std::vector<GpuMeshRange>& meshes() const { return meshes_; }
  const std::vector<Instance>& instances() const { return instances_; }
  const Bounds& bounds() const { return bounds_; }
  size_t triangle_count() const { return triangle_count_; }

 private:
  vk::Buffer positions_;
  vk::Buffer indices_;
  std::vector<GpuMeshRange> meshes_;
  std::vector<Instance> instances_;
  Bounds bounds_;
  size_t triangle_count_ = 0;
};

}  // namespace rtsdf
