#pragma once
// Pass 2b: packing a fine SDF for the shadow march (see PackedField): the
// coarse distances as the far field, and the fine texels in bricks where the
// fine SDF was traced.
#include "shaders/shared.h"
#include "vk/pipeline.h"
#include "vk/resources.h"

namespace rtsdf {

class FieldPackPass {
 public:
  explicit FieldPackPass(const vk::Context& context);
  // Writes the far field from `coarse` (coarse_dims) and, with `fine`, the
  // bricks of `fine` (push.dims; `bricks` of them) near its surfaces,
  // listed in `stored_bricks` (4 words, the first zero and the next two 1,
  // then a word per brick). Word 0 of the store must be zero; the packed
  // words are visible to compute shaders and transfers after it.
  void record(VkCommandBuffer cmd, const gpu::FieldPackPush& push, const vk::Image& coarse, const vk::Image* fine,
              glm::ivec3 bricks, const vk::Buffer& stored_bricks) const;

 private:
  vk::Pipeline far_;
  vk::Pipeline slots_;
  vk::Pipeline bricks_;
};

}  // namespace rtsdf
