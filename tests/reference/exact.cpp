#include "exact.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/type_precision.hpp>
#include <limits>

#include "shaders/shared.h"
#include "vdb_export.h"

namespace rtsdf::reference {

namespace {

using dvec3 = glm::dvec3;

// Akenine-Moeller's separating-axis test against the box centre +- h.
bool overlaps(dvec3 a, dvec3 b, dvec3 c, dvec3 center, double h) {
  dvec3 v[3] = {a - center, b - center, c - center};
  for (int k = 0; k < 3; ++k) {
    double lo = std::min({v[0][k], v[1][k], v[2][k]}), hi = std::max({v[0][k], v[1][k], v[2][k]});
    if (lo > h || hi < -h) return false;
  }
  dvec3 e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  dvec3 n = glm::cross(e[0], e[1]);
  if (std::abs(glm::dot(n, v[0])) > h * (std::abs(n.x) + std::abs(n.y) + std::abs(n.z))) return false;
  for (const dvec3& edge : e)
    for (int k = 0; k < 3; ++k) {
      dvec3 unit(0.0);
      unit[k] = 1.0;
      dvec3 axis = glm::cross(unit, edge);
      double p0 = glm::dot(axis, v[0]), p1 = glm::dot(axis, v[1]), p2 = glm::dot(axis, v[2]);
      double r = h * (std::abs(axis.x) + std::abs(axis.y) + std::abs(axis.z));
      if (std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r) return false;
    }
  return true;
}

template <typename F>
void for_each_world_triangle(const Scene& scene, F&& f) {
  for (const Instance& instance : scene.instances) {
    const Mesh& mesh = scene.meshes[instance.mesh];
    glm::dmat4 m(instance.object_to_world);
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
      dvec3 p[3];
      for (int k = 0; k < 3; ++k) p[k] = dvec3(m * glm::dvec4(dvec3(mesh.positions[mesh.indices[3 * t + k]]), 1.0));
      f(p[0], p[1], p[2]);
    }
  }
}

size_t linear(const GridSpec& g, int x, int y, int z) { return size_t(x) + size_t(g.dims.x) * (y + size_t(g.dims.y) * z); }

}  // namespace

std::vector<uint8_t> surface_voxels(const Scene& scene, const GridSpec& grid, double grow) {
  std::vector<uint8_t> marked(grid.voxel_count(), 0);
  const dvec3 origin(grid.origin);
  const double size = grid.voxel_size;
  for_each_world_triangle(scene, [&](dvec3 a, dvec3 b, dvec3 c) {
    dvec3 va = (a - origin) / size, vb = (b - origin) / size, vc = (c - origin) / size;
    glm::ivec3 lo = glm::ivec3(glm::floor(glm::min(va, glm::min(vb, vc)) - grow));
    glm::ivec3 hi = glm::ivec3(glm::floor(glm::max(va, glm::max(vb, vc)) + grow));
    lo = glm::max(lo, glm::ivec3(0));
    hi = glm::min(hi, grid.dims - 1);
    for (int z = lo.z; z <= hi.z; ++z)
      for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x)
          if (!marked[linear(grid, x, y, z)] && overlaps(va, vb, vc, dvec3(x, y, z) + 0.5, 0.5 + grow))
            marked[linear(grid, x, y, z)] = 1;
  });
  return marked;
}

namespace {

template <typename Build>
std::vector<float> sample_openvdb(const Scene& scene, const GridSpec& grid, Build&& build) {
  openvdb::initialize();
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  for_each_world_triangle(scene, [&](dvec3 a, dvec3 b, dvec3 c) {
    uint32_t base = uint32_t(points.size());
    for (const dvec3& p : {a, b, c}) points.emplace_back(float(p.x), float(p.y), float(p.z));
    triangles.emplace_back(base, base + 1, base + 2);
  });
  auto transform = openvdb_transform(grid);
  openvdb::FloatGrid::Ptr field = build(*transform, points, triangles);
  std::vector<float> values(grid.voxel_count(), std::numeric_limits<float>::infinity());
  auto accessor = field->getConstAccessor();
  for (int z = 0; z < grid.dims.z; ++z)
    for (int y = 0; y < grid.dims.y; ++y)
      for (int x = 0; x < grid.dims.x; ++x) {
        float value;
        if (accessor.probeValue(openvdb::Coord(x, y, z), value)) values[linear(grid, x, y, z)] = value;
      }
  return values;
}

}  // namespace

std::vector<float> unsigned_distance(const Scene& scene, const GridSpec& grid, float band_voxels) {
  return sample_openvdb(scene, grid, [&](auto& transform, auto& points, auto& triangles) {
    return openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(transform, points, triangles,
                                                                          std::vector<openvdb::Vec4I>(), band_voxels);
  });
}

std::vector<float> signed_distance(const Scene& scene, const GridSpec& grid, float band_voxels) {
  return sample_openvdb(scene, grid, [&](auto& transform, auto& points, auto& triangles) {
    return openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(transform, points, triangles, band_voxels);
  });
}

FineErrors compare_fine(const std::vector<float>& fine, const std::vector<float>& exact, const GridSpec& grid,
                        float band_voxels) {
  FineErrors errors;
  double sum = 0;
  size_t signed_count = 0, wrong = 0;
  for (size_t i = 0; i < fine.size(); ++i) {
    float e = exact[i] / grid.voxel_size, f = fine[i] / grid.voxel_size;
    if (!(std::abs(e) <= band_voxels)) continue;
    sum += std::abs(f - e);
    errors.band_voxels++;
    if (std::abs(e) >= 1.0f) {
      signed_count++;
      wrong += (e < 0) != (f < 0);
    }
  }
  errors.mean_abs_voxels = errors.band_voxels ? sum / double(errors.band_voxels) : 0.0;
  errors.wrong_sign_share = signed_count ? double(wrong) / double(signed_count) : 0.0;
  return errors;
}

CoarseErrors compare_coarse(const std::vector<float>& coarse, float beta_world, const std::vector<float>& exact,
                            const std::vector<uint8_t>& surface, const std::vector<uint32_t>& seeds,
                            const GridSpec& grid, float band_voxels) {
  CoarseErrors errors;
  double sum = 0;
  for (size_t i = 0; i < coarse.size(); ++i) {
    if (surface[i]) {
      errors.surface_voxels++;
      if (seeds[i] == gpu::kNoSeed) errors.missing_seeds++;
    }
    float exact_voxels = std::abs(exact[i]) / grid.voxel_size;
    if (!(exact_voxels <= band_voxels)) continue;
    double error = std::abs((coarse[i] + beta_world) / grid.voxel_size - exact_voxels);
    sum += error;
    errors.max_abs_voxels = std::max(errors.max_abs_voxels, error);
    errors.band_voxels++;
  }
  errors.mean_abs_voxels = errors.band_voxels ? sum / double(errors.band_voxels) : 0.0;
  return errors;
}

}  // namespace rtsdf::reference
