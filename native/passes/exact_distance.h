#pragma once
// Pass 1b of an object field's coarse SDF: the exact Euclidean distance
// transform of the seeds (shaders/exact_distance.comp), three passes of one
// line per invocation, in place of the paper's jump flood (which the
// whole-scene fields keep).
#include <array>
#include <map>
#include <memory>

#include "vk/pipeline.h"
#include "vk/resources.h"
#include "vk/timer.h"

namespace rtsdf {

class ExactDistancePass {
 public:
  explicit ExactDistancePass(const vk::Context& context);

  // distance = |voxel centre - nearest seed centre| * voxel_size - beta_world,
  // from `seeds` (left unchanged) through `a` and `b` (squared distances
  // after the x and the y pass). Marks the timer after the last pass.
  void record(VkCommandBuffer cmd, const vk::Image& seeds, const vk::Image& a, const vk::Image& b,
              const vk::Image& distance, float voxel_size, float beta_world, vk::GpuTimer* timer);

 private:
  using AxisPipelines = std::array<std::unique_ptr<vk::Pipeline>, 3>;  // x, y, z
  // The pipelines for lines up to `longest` voxels (made on first use; a
  // context compiles each once).
  const AxisPipelines& pipelines(int longest);

  const vk::Context& context_;
  std::map<int, AxisPipelines> by_line_;
};

}  // namespace rtsdf
