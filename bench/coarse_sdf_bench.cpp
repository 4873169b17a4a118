// Coarse-SDF speed against OpenVDB's narrow-band meshToLevelSet on the same
// mesh and grid, in the same run (the machine is shared: read the ratios).
//
//   rtsdf_bench_coarse [MESH] [--res 64,128,256] [--repeats N]
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "coarse_sdf.h"
#include "mesh_import.h"
#include "vdb_export.h"
#include "vk/context.h"

namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

template <typename F>
double time_ms(F&& f) {
  auto start = Clock::now();
  f();
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double openvdb_build_ms(const rtsdf::Scene& scene, const rtsdf::GridSpec& grid) {
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  for (const rtsdf::Instance& instance : scene.instances) {
    const rtsdf::Mesh& mesh = scene.meshes[instance.mesh];
    uint32_t base = uint32_t(points.size());
    for (const glm::vec3& p : mesh.positions) {
      glm::vec4 w = instance.object_to_world * glm::vec4(p, 1.0f);
      points.emplace_back(w.x, w.y, w.z);
    }
    for (size_t t = 0; t < mesh.triangle_count(); ++t)
      triangles.emplace_back(base + mesh.indices[3 * t], base + mesh.indices[3 * t + 1], base + mesh.indices[3 * t + 2]);
  }
  auto transform = openvdb_transform(grid);
  return time_ms([&] {
    auto level_set = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, points, triangles, 3.0f);
    if (level_set->activeVoxelCount() == 0) std::fprintf(stderr, "warning: empty OpenVDB level set\n");
  });
}

}  // namespace

int main(int argc, char** argv) {
  std::string mesh_path = RTSDF_BENCH_MESH;
  std::vector<int> resolutions{64, 128, 256};
  int repeats = 5;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--res") && i + 1 < argc) {
      resolutions.clear();
      std::stringstream list(argv[++i]);
      for (std::string item; std::getline(list, item, ',');) resolutions.push_back(std::stoi(item));
    } else if (!std::strcmp(argv[i], "--repeats") && i + 1 < argc) {
      repeats = std::max(1, std::atoi(argv[++i]));
    } else if (!std::strcmp(argv[i], "--help")) {
      std::printf("usage: rtsdf_bench_coarse [MESH] [--res 64,128,256] [--repeats N]\n");
      return 0;
    } else {
      mesh_path = argv[i];
    }
  }
  try {
    openvdb::initialize();
    rtsdf::Scene scene = rtsdf::import_scene(mesh_path);
    rtsdf::vk::Context context;
    rtsdf::GpuScene gpu_scene(context, scene);
    rtsdf::CoarseSdf coarse(context);
    std::printf("mesh %s: %zu triangles; device %s; median of %d runs after one warm-up\n", mesh_path.c_str(),
                scene.triangle_count(), context.info().name.c_str(), repeats);
    std::printf("%5s %14s %10s %9s %13s %10s %10s %10s %12s %8s\n", "res", "dims", "voxelize", "jfa/pass",
                "jfa(passes)", "gpu_total", "wall", "openvdb", "openvdb/wall", "");
    for (int resolution : resolutions) {
      rtsdf::GridSpec grid = rtsdf::fit_grid(gpu_scene.bounds(), resolution);
      coarse.build(gpu_scene, grid, 0.5f);  // warm-up: allocation and shader variants
      std::vector<double> voxelize, per_pass, gpu_total, wall, openvdb;
      size_t passes = 0;
      for (int r = 0; r < repeats; ++r) {
        wall.push_back(time_ms([&] { coarse.build(gpu_scene, grid, 0.5f); }));
        const rtsdf::CoarseSdfTimings& t = coarse.timings();
        voxelize.push_back(t.voxelize_ms);
        per_pass.push_back(t.jump_flood_ms / double(t.pass_ms.size()));
        passes = t.pass_ms.size();
        gpu_total.push_back(t.gpu_total_ms);
        openvdb.push_back(openvdb_build_ms(scene, grid));
      }
      char dims[32];
      std::snprintf(dims, sizeof dims, "%dx%dx%d", grid.dims.x, grid.dims.y, grid.dims.z);
      std::printf("%5d %14s %10.1f %9.1f %10.1f(%zu) %10.1f %10.1f %10.1f %12.2f %8s\n", resolution, dims,
                  median(voxelize), median(per_pass), median(per_pass) * double(passes), passes, median(gpu_total),
                  median(wall), median(openvdb), median(openvdb) / median(wall),
                  median(openvdb) >= median(wall) ? "faster" : "slower");
    }
    std::printf("ms per stage; openvdb = narrow-band meshToLevelSet (half width 3 voxels) on the same grid;\n"
                "openvdb/wall > 1 means the coarse SDF (whole grid) was built faster than OpenVDB's band.\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rtsdf_bench_coarse: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
