// The .vdb written for a coarse SDF reads back with the right name, class,
// transform and values.
#include <openvdb/openvdb.h>

#include "coarse_sdf.h"
#include "reference/shapes.h"
#include "vdb_export.h"
#include "vulkan_test.h"

namespace rtsdf {
namespace {

class VdbExport : public testing::VulkanTest {};

TEST_F(VdbExport, RoundTripKeepsNameClassTransformAndValues) {
  GpuScene scene(context(), single_mesh_scene(reference::uv_sphere({0.2f, 0, 0}, 1.0f, 64)));
  GridSpec grid = fit_grid(scene.bounds(), 32);
  CoarseSdf coarse(context());
  coarse.build(scene, grid, 0.5f);
  std::vector<float> distance = coarse.read_distance();
  const std::string path = ::testing::TempDir() + "rtsdf_roundtrip.vdb";
  write_vdb(path, {{"coarse", grid, &distance}});

  openvdb::initialize();
  openvdb::io::File file(path);
  file.open();
  openvdb::FloatGrid::Ptr read = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("coarse"));
  file.close();
  ASSERT_TRUE(read);
  EXPECT_EQ(read->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_NEAR(read->voxelSize()[0], grid.voxel_size, 1e-7);
  auto accessor = read->getConstAccessor();
  for (glm::ivec3 v : {glm::ivec3(0), glm::ivec3(5, 7, 9), grid.dims - 1, grid.dims / 2}) {
    size_t i = size_t(v.x) + size_t(grid.dims.x) * (v.y + size_t(grid.dims.y) * v.z);
    EXPECT_FLOAT_EQ(accessor.getValue(openvdb::Coord(v.x, v.y, v.z)), distance[i]);
    openvdb::Vec3d world = read->indexToWorld(openvdb::Coord(v.x, v.y, v.z));
    glm::vec3 expected = grid.voxel_center(v);
    EXPECT_NEAR(world.x(), expected.x, 1e-5);
    EXPECT_NEAR(world.y(), expected.y, 1e-5);
    EXPECT_NEAR(world.z(), expected.z, 1e-5);
  }
  // Inside the sphere's shell near its centre-to-surface midpoint the field is
  // positive (jump flooding is unsigned away from the surface), at the surface negative.
  openvdb::Coord surface = read->transform().worldToIndexCellCentered(openvdb::Vec3d(1.2, 0, 0));
  EXPECT_LT(accessor.getValue(surface), 0.0f);
}

}  // namespace
}  // namespace rtsdf
