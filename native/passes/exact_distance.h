#pragma once
// Pass 1b of an object field's coarse SDF: the exact Euclidean distance
// transform of the seeds (shaders/exact_distance.comp), three passes of one
// line per invocation, in place of the paper's jump flood (which the
// whole-scene fields keep).
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
              const vk::Image& distance, float voxel_size, float beta_world, vk::GpuTimer* timer) const;

 private:
  vk::Pipeline axis_x_, axis_y_, axis_z_;
};

}  // namespace rtsdf
