#pragma once
// Pass 1b: 3D jump flooding of the seeds (the 1+JFA variant), then the
// conversion of nearest-seed indices to the coarse signed distance.
#include <vector>

#include "grid.h"
#include "vk/pipeline.h"
#include "vk/resources.h"
#include "vk/timer.h"

namespace rtsdf {

class JumpFloodPass {
 public:
  explicit JumpFloodPass(const vk::Context& context);

  // Step lengths of 1+JFA: one pass of step 1 first, then N/2, N/4, ..., 1 with
  // N the grid's longest axis rounded up to a power of two. The extra first
  // pass fixes most of plain JFA's errors (Rong and Tan 2006) as well as two
  // extra passes at the end would, for the price of one.
  static std::vector<int> steps(glm::ivec3 dims);

  // Floods from `seeds` (left unchanged) through `a` and `b` in turn.
  // Returns the image that holds the result. Marks the timer after each pass.
  const vk::Image& record_flood(VkCommandBuffer cmd, const vk::Image& seeds, const vk::Image& a,
                                  const vk::Image& b, vk::GpuTimer* timer) const;
  // distance = |voxel centre - nearest seed centre| * voxel_size - beta_world.
  void record_distance(VkCommandBuffer cmd, const vk::Image& seeds, const vk::Image& distance,
                       float voxel_size, float beta_world) const;

 private:
  vk::Pipeline flood_;
  vk::Pipeline distance_;
};

}  // namespace rtsdf
