#pragma once
// Writes dense SDFs as OpenVDB level-set FloatGrids that Blender and Houdini open.
#include <openvdb/math/Transform.h>

#include <string>
#include <vector>

#include "grid.h"

namespace rtsdf {

struct NamedField {
  std::string name;           // grid name in the file, e.g. "coarse"
  GridSpec grid;              // voxel (i,j,k) -> world centre origin + (ijk + 0.5) * voxel_size
  const std::vector<float>* values;  // world units, negative inside; x fastest
};

// OpenVDB transform of `grid`: index (i,j,k) -> world centre of that voxel.
openvdb::math::Transform::Ptr openvdb_transform(const GridSpec& grid);

// Throws rtsdf::Error if the file cannot be written.
void write_vdb(const std::string& path, const std::vector<NamedField>& fields);

}  // namespace rtsdf
