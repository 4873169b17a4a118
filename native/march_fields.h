#pragma once
// What the shadow march reads (shaders/sdf_fields.glsl.h): packed distance
// fields (each in its own words, see PackedField) placed in the world by
// instances, and a BVH over the instances' world boxes. The object-space
// design places one field per mesh once per instance; the whole-scene
// methods place their one field with the identity.
#include <vector>

#include "grid.h"
#include "packed_field.h"
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

  struct Placement {
    const PackedField* field;  // must stay at its address (PackedField::generation) while placed
    glm::mat4 object_to_world;
  };
  // Places the fields (replacing every earlier placement) and uploads the
  // instances and their BVH. Placements whose transform is degenerate
  // (kDegenerateScale) are left out and counted in skipped_degenerate().
  void place(const std::vector<Placement>& placements);

  const vk::Buffer& instances() const { return instances_; }
  const vk::Buffer& nodes() const { return nodes_; }
  uint32_t instance_count() const { return instance_count_; }
  // World size of the coarsest placed voxel (0 with nothing placed).
  float largest_voxel() const { return largest_voxel_; }
  // World size of a voxel of `field` under `object_to_world`, as the
  // shading's thresholds use it (the largest stretch).
  static float world_voxel(const PackedField& field, const glm::mat4& object_to_world);
  uint32_t skipped_degenerate() const { return skipped_degenerate_; }

 private:
  const vk::Context& context_;
  vk::Buffer instances_;
  vk::Buffer nodes_;
  uint32_t instance_count_ = 0;
  float largest_voxel_ = 0.0f;
  uint32_t skipped_degenerate_ = 0;
};

}  // namespace rtsdf
