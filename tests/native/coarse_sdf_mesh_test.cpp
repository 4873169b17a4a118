// The coarse SDF of a real CAD-like mesh against OpenVDB's exact distance.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "coarse_sdf.h"
#include "mesh_import.h"
#include "reference/exact.h"
#include "vulkan_test.h"


namespace rtsdf {
namespace {

class CoarseSdfMesh : public testing::VulkanTest, public ::testing::WithParamInterface<int> {};

TEST_P(CoarseSdfMesh, MatchesOpenVdbAndLeavesNoHoles) {
  const int resolution = GetParam();
  const std::string mesh = testing::test_mesh_path();
  Scene scene = import_scene(mesh);
  GpuScene gpu_scene(context(), scene);
  GridSpec grid = fit_grid(gpu_scene.bounds(), resolution);
  CoarseSdf coarse(context());
  coarse.build(gpu_scene, grid, 0.5f);

  const float band = 3.0f;
  reference::CoarseErrors errors = reference::compare_coarse(
      coarse.read_distance(), coarse.beta_world(), reference::unsigned_distance(scene, grid, band + 1.0f),
      reference::surface_voxels(scene, grid), coarse.read_seeds(), grid, band);
  std::printf("%s at %d (%dx%dx%d): mean |coarse+beta-|exact|| %.3f voxels, max %.3f over %zu band voxels; "
              "%zu of %zu surface voxels without a seed (%.4f%%); voxelize %.1f ms, jump flood %.1f ms\n",
              mesh.c_str(), resolution, grid.dims.x, grid.dims.y, grid.dims.z, errors.mean_abs_voxels,
              errors.max_abs_voxels, errors.band_voxels, errors.missing_seeds, errors.surface_voxels,
              100.0 * errors.hole_share(), coarse.timings().voxelize_ms, coarse.timings().jump_flood_ms);
  EXPECT_LE(errors.mean_abs_voxels, 0.6);
  EXPECT_LT(errors.hole_share(), 0.01);
  EXPECT_EQ(errors.missing_seeds, 0u);
}

INSTANTIATE_TEST_SUITE_P(Resolutions, CoarseSdfMesh, ::testing::Values(64, 128));

}  // namespace
}  // namespace rtsdf
