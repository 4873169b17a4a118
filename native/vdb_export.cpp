#include "vdb_export.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>

#include <algorithm>

#include "error.h"

namespace rtsdf {

namespace {

openvdb::FloatGrid::Ptr to_grid(const NamedField& field) {
  const GridSpec& g = field.grid;
  const std::vector<float>& values = *field.values;
  if (values.size() != g.voxel_count()) throw Error("field '" + field.name + "' does not match its grid");
  // Beyond the grid reads as "far outside": the largest distance stored.
  const float background = values.empty() ? 0.0f : *std::max_element(values.begin(), values.end());
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(background);
  openvdb::CoordBBox box(openvdb::Coord(0), openvdb::Coord(g.dims.x - 1, g.dims.y - 1, g.dims.z - 1));
  // LayoutXYZ: x varies fastest, as in our buffers.
  openvdb::tools::Dense<const float, openvdb::tools::LayoutXYZ> dense(box, values.data());
  openvdb::tools::copyFromDense(dense, *grid, /*tolerance=*/0.0f);
  grid->setTransform(openvdb_transform(g));
  grid->setName(field.name);
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  return grid;
}

}  // namespace

openvdb::math::Transform::Ptr openvdb_transform(const GridSpec& grid) {
  auto transform = openvdb::math::Transform::createLinearTransform(grid.voxel_size);
  transform->postTranslate(openvdb::Vec3d(grid.origin.x, grid.origin.y, grid.origin.z) + 0.5 * double(grid.voxel_size));
  return transform;
}

void write_vdb(const std::string& path, const std::vector<NamedField>& fields) {
  openvdb::initialize();
  openvdb::GridPtrVec grids;
  for (const NamedField& field : fields) grids.push_back(to_grid(field));
  try {
    openvdb::io::File file(path);
    file.write(grids);
    file.close();
  } catch (const openvdb::Exception& e) {
    throw Error("cannot write '" + path + "': " + e.what());
  }
}

}  // namespace rtsdf
