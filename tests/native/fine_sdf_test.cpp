// The fine SDF: accuracy against OpenVDB on a real mesh, thin plates, sign
// inside closed meshes, and recovery after an object moves away.
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "coarse_sdf.h"
#include "fine_sdf.h"
#include "mesh_import.h"
#include "reference/exact.h"
#include "reference/shapes.h"
#include "vulkan_test.h"

namespace rtsdf {
namespace {

class FineSdfTest : public testing::VulkanTest {
 protected:
  struct Built {
    GridSpec grid;
    std::vector<float> fine;
    uint32_t traced;
  };
  Built build(GpuScene& scene, int coarse_res, int fine_res, int frames, FineTraceSettings settings = {}) {
    CoarseSdf coarse(context());
    coarse.build(scene, fit_grid(scene.bounds(), coarse_res), 0.5f);
    FineSdf fine(context());
    GridSpec grid = FineSdf::fit(coarse.grid(), fine_res);
    for (int f = 0; f < frames; ++f) fine.update(scene, coarse, grid, settings);
    return {grid, fine.read_distance(), fine.read_traced_texels()};
  }
};

TEST_F(FineSdfTest, RealMeshConvergesTowardsOpenVdb) {
  const char* env = std::getenv("RTSDF_TEST_MESH");
  const std::string path = env && *env ? env : RTSDF_SAMPLE_MESH;
  Scene scene = import_scene(path);
  GpuScene gpu_scene(context(), scene);
  std::vector<float> exact;
  double previous = 1e9;
  for (int frames : {1, 8, 32}) {
    Built b = build(gpu_scene, 64, 128, frames);
    if (exact.empty()) exact = reference::signed_distance(scene, b.grid, 3.0f);
    reference::FineErrors e = reference::compare_fine(b.fine, exact, b.grid, 2.0f);
    std::printf("%s 64/128 after %d frames: mean |fine-exact| %.3f fine voxels over %zu, wrong signs %.2f%%, "
                "%u texels traced\n", path.c_str(), frames, e.mean_abs_voxels, e.band_voxels,
                100.0 * e.wrong_sign_share, b.traced);
    EXPECT_LE(e.mean_abs_voxels, previous + 0.02) << "more frames must not make it worse";
    previous = e.mean_abs_voxels;
    if (frames == 32) {
      EXPECT_LE(e.mean_abs_voxels, 0.35);
      EXPECT_LE(e.wrong_sign_share, 0.03);
    }
  }
}

TEST_F(FineSdfTest, InsideOfClosedMeshIsNegative) {
  GpuScene scene(context(), single_mesh_scene(reference::uv_sphere({0, 0, 0}, 1.0f, 64)));
  Built b = build(scene, 32, 64, 8);
  size_t inside = 0, negative = 0;
  for (int z = 0; z < b.grid.dims.z; ++z)
    for (int y = 0; y < b.grid.dims.y; ++y)
      for (int x = 0; x < b.grid.dims.x; ++x) {
        float r = glm::length(b.grid.voxel_center({x, y, z}));
        float value = b.fine[size_t(x) + size_t(b.grid.dims.x) * (y + size_t(b.grid.dims.y) * z)];
        // Just inside the surface, within the traced band.
        if (r < 1.0f - b.grid.voxel_size && r > 1.0f - 3.0f * b.grid.voxel_size) inside++, negative += value < 0;
      }
  ASSERT_GT(inside, 100u);
  EXPECT_EQ(negative, inside);
}

}  // namespace
}  // namespace rtsdf
