#pragma once
// Helpers shared by the benchmarks: timing, medians, and OpenVDB's
// narrow-band build of the same scene on the same grid (the peer we compare to).
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "grid.h"
#include "scene.h"
#include "vdb_export.h"

namespace rtsdf::bench {

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

template <typename F>
double time_ms(F&& f) {
  auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Milliseconds of openvdb::tools::meshToLevelSet (half width 3 voxels) on `grid`.
inline double openvdb_build_ms(const Scene& scene, const GridSpec& grid) {
  openvdb::initialize();
  const Mesh placed = placed_mesh(scene);
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  for (const glm::vec3& p : placed.positions) points.emplace_back(p.x, p.y, p.z);
  for (size_t t = 0; t < placed.triangle_count(); ++t)
    triangles.emplace_back(placed.indices[3 * t], placed.indices[3 * t + 1], placed.indices[3 * t + 2]);
  auto transform = openvdb_transform(grid);
  return time_ms([&] {
    auto level_set = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, points, triangles, 3.0f);
    if (level_set->activeVoxelCount() == 0) std::fprintf(stderr, "warning: empty OpenVDB level set\n");
  });
}

}  // namespace rtsdf::bench
