// A mesh's feature size (how thin its parts and the gaps between them are)
// and the factor it puts on the mesh's field resolution.
#include "mesh_detail.h"

#include <gtest/gtest.h>

#include <cmath>

#include "reference/shapes.h"

namespace rtsdf {
namespace {

float feature_size(const Mesh& mesh) { return mesh_feature_size(mesh, build_mesh_bvh(mesh)); }

TEST(MeshDetailTest, FeatureSizeIsHowThinThePartsAndTheGapsBetweenThemAre) {
  EXPECT_NEAR(feature_size(reference::box({-1, -1, 0}, {1, 1, 0.1f})), 0.1f, 1e-3f) << "a slab: its thickness";
  EXPECT_NEAR(feature_size(reference::box({0, 0, 0}, {1, 1, 1})), 1.0f, 1e-3f) << "a cube: its side";
  EXPECT_NEAR(feature_size(reference::uv_sphere({0, 0, 0}, 0.5f, 32)), 1.0f, 0.02f) << "a sphere: its diameter";
  Mesh two_sheets = reference::sheet({-1, -1}, {1, 1}, 0.0f);
  reference::append(two_sheets, reference::sheet({-1, -1}, {1, 1}, 0.05f));
  EXPECT_NEAR(feature_size(two_sheets), 0.05f, 1e-3f) << "two sheets (open, no inside): the gap between them";
  EXPECT_TRUE(std::isinf(feature_size(reference::sheet({-1, -1}, {1, 1}, 0.0f)))) << "a lone sheet meets nothing";
  EXPECT_TRUE(std::isinf(feature_size(Mesh{}))) << "no triangles";
  Mesh degenerate;
  degenerate.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  degenerate.indices = {0, 1, 2};
  EXPECT_TRUE(std::isinf(feature_size(degenerate))) << "no area";
}

TEST(MeshDetailTest, ResolutionRisesUntilThinPartsSpanAVoxelUpToACap) {
  EXPECT_FLOAT_EQ(detail_scale(0.5f, 10.0f, 100), 1.0f) << "parts wider than the voxel (0.1): its size's resolution";
  EXPECT_FLOAT_EQ(detail_scale(0.08f, 10.0f, 100), 1.25f) << "a voxel across the thin parts";
  EXPECT_FLOAT_EQ(detail_scale(0.001f, 10.0f, 100), kMaxDetailScale) << "capped";
  EXPECT_FLOAT_EQ(detail_scale(INFINITY, 10.0f, 100), 1.0f) << "nothing thin";
  EXPECT_FLOAT_EQ(detail_scale(0.0f, 10.0f, 100), kMaxDetailScale) << "faces on top of each other";
  EXPECT_FLOAT_EQ(detail_scale(NAN, 10.0f, 100), 1.0f);
}

}  // namespace
}  // namespace rtsdf
