// The packed field the shadow march reads: every texel of the fine SDF (its
// bricks near surfaces, the far field elsewhere) in a fraction of the dense
// grid's memory, packed exactly where bricks fill the whole grid.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>

#include "coarse_sdf.h"
#include "fine_sdf.h"
#include "mesh_import.h"
#include "packed_field.h"
#include "reference/shapes.h"
#include "vulkan_test.h"

namespace rtsdf {
namespace {

class PackedFieldTest : public testing::VulkanTest {
 protected:
  // Packs `fine` (over `coarse`); returns how many packs it took.
  int pack(PackedField& packed, const CoarseSdf& coarse, const FineSdf& fine, const FineTraceSettings& settings) {
    packed.set_layout(fine.grid(), coarse.grid(), Bounds{coarse.grid().origin, coarse.grid().origin});
    const PackedField::Source source{&coarse.distance(), &fine.distance(),
                                     settings.band_world(coarse.grid().voxel_size), coarse.beta_world()};
    int packs = 0;
    for (bool done = false; !done && packs < 4;) {
      context().submit_and_wait([&](VkCommandBuffer cmd) { packed.record_pack(cmd, source); });
      done = packed.settle();
      packs++;
    }
    return packs;
  }

  // The largest gap between the packed texels and the fine SDF's, in fine
  // voxels, over what half floats allow (1 where it is just that).
  double worst_gap(const PackedField& packed, const FineSdf& fine) {
    const std::vector<float> dense = fine.read_distance(), read = packed.read_texels();
    EXPECT_EQ(read.size(), dense.size());
    const float voxel = fine.grid().voxel_size;
    double worst = 0.0;
    for (size_t i = 0; i < std::min(read.size(), dense.size()); ++i) {
      // Half floats keep 11 bits; far texels are interpolated from coarse
      // ones up to two fine voxels farther away.
      const double allowed = 1e-3 * (std::abs(dense[i]) / voxel + 2.0);
      worst = std::max(worst, std::abs(double(read[i]) - dense[i]) / voxel / allowed);
    }
    return worst;
  }
};

TEST_F(PackedFieldTest, HoldsEveryTexelOfARealMeshInAQuarterOfTheDenseMemory) {
  Scene scene = import_scene(testing::test_mesh_path());
  GpuScene gpu_scene(context(), scene);
  CoarseSdf coarse(context());
  coarse.build(gpu_scene, fit_grid(gpu_scene.bounds(), 64), 0.5f);
  FineSdf fine(context());
  const FineTraceSettings settings;
  for (int frame = 0; frame < 4; ++frame) fine.update(gpu_scene, coarse, FineSdf::fit(coarse.grid(), 128), settings);
  PackedField packed(context());
  EXPECT_EQ(pack(packed, coarse, fine, settings), 2) << "a first pack counts the bricks, the second stores them";
  EXPECT_EQ(pack(packed, coarse, fine, settings), 1) << "refining the same field needs no more room";
  const double gap = worst_gap(packed, fine);
  const size_t fine_texels = fine.grid().voxel_count() * sizeof(float);
  const size_t dense = coarse.bytes() + fine.bytes() + fine_texels;  // the SDFs' images and a dense copy to march
  std::printf("%u of %u bricks stored, %.2f MB against %.2f MB of dense fine texels (%.2f MB with the SDFs); "
              "worst gap %.2f of the half-float allowance\n", packed.stored_bricks(), packed.brick_count(),
              packed.bytes() / 1048576.0, fine_texels / 1048576.0, dense / 1048576.0, gap);
  EXPECT_LE(gap, 1.0);
  EXPECT_GT(packed.stored_bricks(), 0u);
  EXPECT_LT(packed.stored_bricks(), packed.brick_count() * 6 / 10);
  EXPECT_LT(packed.bytes(), fine_texels / 2) << "half the fine texels alone, dense in 32-bit floats";
  EXPECT_LE(packed.bytes(), dense / 4);
}

// The renderer's fields classify and trace only the bricks near surfaces
// (FineTraceSettings::near_surface_only): what they pack is the field a
// whole-grid classify packs, texel for texel.
TEST_F(PackedFieldTest, ClassifyingNearSurfacesOnlyPacksTheSameField) {
  Scene scene = import_scene(testing::test_mesh_path());
  GpuScene gpu_scene(context(), scene);
  CoarseSdf coarse(context());
  coarse.build(gpu_scene, fit_grid(gpu_scene.bounds(), 48), 0.5f);
  const GridSpec grid = FineSdf::fit(coarse.grid(), 96);
  FineTraceSettings whole_grid, near_surface_only;
  whole_grid.interleave = near_surface_only.interleave = 2;
  near_surface_only.near_surface_only = true;
  FineSdf fine_whole(context()), fine_near(context());
  uint32_t traced_whole = 0, traced_near = 0;
  for (int frame = 0; frame < 3; ++frame) {
    fine_whole.update(gpu_scene, coarse, grid, whole_grid);
    fine_near.update(gpu_scene, coarse, grid, near_surface_only);
    traced_whole += fine_whole.read_traced_texels();
    traced_near += fine_near.read_traced_texels();
  }
  PackedField packed_whole(context()), packed_near(context());
  pack(packed_whole, coarse, fine_whole, whole_grid);
  pack(packed_near, coarse, fine_near, near_surface_only);
  const std::vector<float> whole = packed_whole.read_texels(), near = packed_near.read_texels();
  ASSERT_EQ(whole.size(), near.size());
  size_t different = 0;
  for (size_t i = 0; i < whole.size(); ++i) different += whole[i] != near[i];
  std::printf("near surfaces only: %u of %u bricks stored, %zu of %zu texels differ; traced %u texels, the whole grid %u\n",
              packed_near.stored_bricks(), packed_near.brick_count(), different, whole.size(), traced_near, traced_whole);
  EXPECT_EQ(packed_near.stored_bricks(), packed_whole.stored_bricks());
  EXPECT_EQ(different, 0u);
  EXPECT_LE(traced_near, traced_whole);
}

TEST_F(PackedFieldTest, PacksAFieldWithBricksEverywhere) {
  // A lattice of small spheres fills the grid: bricks everywhere.
  Scene scene;
  scene.meshes.push_back(reference::uv_sphere({0.0f, 0.0f, 0.0f}, 0.15f, 8));
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      for (int k = 0; k < 6; ++k)
        scene.instances.push_back({0, glm::translate(glm::mat4(1.0f), 0.4f * glm::vec3(i, j, k))});
  GpuScene gpu_scene(context(), scene);
  CoarseSdf coarse(context());
  coarse.build(gpu_scene, fit_grid(gpu_scene.bounds(), 32), 0.5f);
  FineSdf fine(context());
  const FineTraceSettings settings;
  fine.update(gpu_scene, coarse, FineSdf::fit(coarse.grid(), 96), settings);
  PackedField packed(context());
  packed.set_layout(fine.grid(), coarse.grid(), gpu_scene.bounds());
  const uint64_t laid_out = packed.generation();
  const int packs = pack(packed, coarse, fine, settings);
  EXPECT_EQ(packs, 2);
  EXPECT_GT(packed.generation(), laid_out) << "more room is a new allocation: placements must be redone";
  EXPECT_GT(packed.stored_bricks(), packed.brick_count() * 9 / 10);
  EXPECT_LE(worst_gap(packed, fine), 1.0);
}

}  // namespace
}  // namespace rtsdf
