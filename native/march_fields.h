#pragma once
// What the shadow march reads (shaders/sdf_fields.glsl.h): the texels of
// every distance field in one pool buffer, the fields placed in the world by
// instances, and a BVH over the instances' world boxes. The object-space
// design places one field per mesh once per instance; the whole-scene
// methods place their one field with the identity.
#include <vector>

#include "grid.h"
#include "shaders/shared.h"
#include "vk/resources.h"

namespace rtsdf {

// Smallest and largest singular values of a 3x3 matrix (how much it shrinks
// and stretches lengths at most).
glm::vec2 singular_value_range(const glm::mat3& m);

// A transform whose smallest stretch is this small against its largest
// (flattened to a plane or a line) cannot carry a field's distances.
constexpr float kDegenerateScale = 1e-4f;

class MarchFields {
 public:
  explicit MarchFields(const vk::Context& context);

  // Lays the fields out in the pool, one per grid (the grids of their own
  // spaces), each holding surfaces within `contents` (same order and space).
  // The march reads a field within its content grown by `rooms` voxels (one
  // per field; none: the whole grid), as far as the grid goes: it knows
  // nothing lies in the margin between. Keeps the pool (and what was copied
  // into it) when the dims are the same as before; returns whether it was
  // laid out anew, in which case every field must be copied in again.
  bool set_layout(const std::vector<GridSpec>& grids, const std::vector<Bounds>& contents,
                  const std::vector<float>& rooms = {});
  // Records a copy of field `field`'s distances (an r32f image of its grid's
  // dims, in GENERAL layout) into the pool.
  void record_copy(VkCommandBuffer cmd, uint32_t field, const vk::Image& distance) const;
  // Makes the copies recorded before it visible to the shading.
  static void record_copies_done(VkCommandBuffer cmd);

  struct Placement {
    uint32_t field;
    glm::mat4 object_to_world;
  };
  // Places the fields (replacing every earlier placement) and uploads the
  // instances and their BVH. Placements whose transform is degenerate
  // (kDegenerateScale) are left out and counted in skipped_degenerate().
  void place(const std::vector<Placement>& placements);

  const vk::Buffer& texels() const { return texels_; }
  const vk::Buffer& instances() const { return instances_; }
  const vk::Buffer& nodes() const { return nodes_; }
  uint32_t instance_count() const { return instance_count_; }
  // World size of the coarsest placed voxel (0 with nothing placed).
  float largest_voxel() const { return largest_voxel_; }
  // World size of a voxel of field `field` under `object_to_world`, as the
  // shading's thresholds use it (the largest stretch).
  float world_voxel(uint32_t field, const glm::mat4& object_to_world) const;
  size_t pool_bytes() const { return size_t(texels_.size()); }
  uint32_t skipped_degenerate() const { return skipped_degenerate_; }

 private:
  const vk::Context& context_;
  std::vector<GridSpec> grids_;
  std::vector<float> margins_;  // voxels, per field
  std::vector<glm::vec3> box_lo_, box_hi_;  // what the march reads of each field, in its voxels
  std::vector<uint32_t> first_texel_;
  vk::Buffer texels_;
  vk::Buffer instances_;
  vk::Buffer nodes_;
  uint32_t instance_count_ = 0;
  float largest_voxel_ = 0.0f;
  uint32_t skipped_degenerate_ = 0;
};

}  // namespace rtsdf
