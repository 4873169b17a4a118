#pragma once
// Ground truth for the coarse SDF: exact voxelization and exact distances.
#include <cstdint>
#include <vector>

#include "grid.h"
#include "scene.h"

namespace rtsdf::reference {

// 1 for every voxel of `grid` that a triangle of `scene` overlaps (exact
// triangle/box test in double precision, boxes grown by `grow` voxels).
std::vector<uint8_t> surface_voxels(const Scene& scene, const GridSpec& grid, double grow = 0.0);

// Exact unsigned distance (world units) from every voxel centre to the scene's
// triangles within `band_voxels` of them (OpenVDB meshToUnsignedDistanceField);
// farther voxels read as +infinity.
std::vector<float> unsigned_distance(const Scene& scene, const GridSpec& grid, float band_voxels);

// Exact signed distance (OpenVDB meshToLevelSet, negative inside closed
// surfaces) within `band_voxels`; farther voxels read as +-infinity.
std::vector<float> signed_distance(const Scene& scene, const GridSpec& grid, float band_voxels);

struct FineErrors {
  double mean_abs_voxels = 0;   // mean |fine - exact| where |exact| <= band
  size_t band_voxels = 0;
  double wrong_sign_share = 0;  // among voxels with 1 <= |exact| <= band
};
FineErrors compare_fine(const std::vector<float>& fine, const std::vector<float>& exact, const GridSpec& grid,
                        float band_voxels);

struct CoarseErrors {
  double mean_abs_voxels = 0;  // mean |coarse + beta - |exact|| over the band
  double max_abs_voxels = 0;
  size_t band_voxels = 0;      // voxels with |exact| <= band
  size_t surface_voxels = 0;   // voxels a triangle overlaps
  size_t missing_seeds = 0;    // surface voxels without a seed
  double hole_share() const { return surface_voxels ? double(missing_seeds) / double(surface_voxels) : 0.0; }
};

// Compares a coarse SDF (world units, x fastest) with exact distances.
CoarseErrors compare_coarse(const std::vector<float>& coarse, float beta_world, const std::vector<float>& exact,
                            const std::vector<uint8_t>& surface, const std::vector<uint32_t>& seeds,
                            const GridSpec& grid, float band_voxels);

}  // namespace rtsdf::reference
