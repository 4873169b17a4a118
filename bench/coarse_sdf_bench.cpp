// Coarse-SDF speed against OpenVDB's narrow-band meshToLevelSet on the same
// mesh and grid, in the same run (the machine is shared: read the ratios).
//
//   rtsdf_bench_coarse [MESH] [--res 64,128,256] [--repeats N]
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bench_common.h"
#include "coarse_sdf.h"
#include "mesh_import.h"
#include "vk/context.h"

using rtsdf::bench::median;
using rtsdf::bench::openvdb_build_ms;
using rtsdf::bench::time_ms;

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
    // A mesh's own field (build_mesh) takes the exact distance transform in
    // place of the flood: the same seeds, when the file holds one mesh placed as it is.
    const bool one_mesh = scene.meshes.size() == 1 && scene.instances.size() == 1 &&
                          scene.instances[0].object_to_world == glm::mat4(1.0f);
    std::printf("%5s %14s %10s %9s %13s %10s %10s %10s %12s %8s %10s\n", "res", "dims", "voxelize", "jfa/pass",
                "jfa(passes)", "gpu_total", "wall", "openvdb", "openvdb/wall", "", "exact");
    for (int resolution : resolutions) {
      rtsdf::GridSpec grid = rtsdf::fit_grid(gpu_scene.bounds(), resolution);
      coarse.build(gpu_scene, grid, 0.5f);  // warm-up: allocation and shader variants
      std::vector<double> voxelize, per_pass, gpu_total, wall, openvdb, exact;
      size_t passes = 0;
      for (int r = 0; r < repeats; ++r) {
        wall.push_back(time_ms([&] { coarse.build(gpu_scene, grid, 0.5f); }));
        const rtsdf::CoarseSdfTimings& t = coarse.timings();
        voxelize.push_back(t.voxelize_ms);
        per_pass.push_back(t.jump_flood_ms / double(t.pass_ms.size()));
        passes = t.pass_ms.size();
        gpu_total.push_back(t.gpu_total_ms);
        openvdb.push_back(openvdb_build_ms(scene, grid));
        if (one_mesh) {
          coarse.build_mesh(gpu_scene, 0, grid, 0.5f);
          exact.push_back(coarse.timings().exact_distance_ms);
        }
      }
      char dims[32];
      std::snprintf(dims, sizeof dims, "%dx%dx%d", grid.dims.x, grid.dims.y, grid.dims.z);
      char exact_ms[32] = "-";
      if (one_mesh) std::snprintf(exact_ms, sizeof exact_ms, "%.1f", median(exact));
      std::printf("%5d %14s %10.1f %9.1f %10.1f(%zu) %10.1f %10.1f %10.1f %12.2f %8s %10s\n", resolution, dims,
                  median(voxelize), median(per_pass), median(per_pass) * double(passes), passes, median(gpu_total),
                  median(wall), median(openvdb), median(openvdb) / median(wall),
                  median(openvdb) >= median(wall) ? "faster" : "slower", exact_ms);
    }
    std::printf("ms per stage; openvdb = narrow-band meshToLevelSet (half width 3 voxels) on the same grid;\n"
                "openvdb/wall > 1 means the coarse SDF (whole grid) was built faster than OpenVDB's band;\n"
                "exact = the exact distance transform of the same seeds (a mesh's own field), against jfa(passes).\n");

    // The whole command a user runs (load, Vulkan start-up, build, read-back,
    // .vdb write), as a separate process, beside OpenVDB's build alone.
    std::printf("\nwhole 'rtsdf sdf' process against OpenVDB's build alone (median of %d):\n", repeats);
    for (int resolution : resolutions) {
      const std::string json = "/tmp/rtsdf_bench_coarse.json", vdb = "/tmp/rtsdf_bench_coarse.vdb";
      const std::string command = std::string(RTSDF_CLI) + " sdf '" + mesh_path + "' --coarse-res " +
                                  std::to_string(resolution) + " --out " + vdb + " --json " + json + " > /dev/null";
      std::vector<double> process, openvdb;
      for (int r = 0; r < repeats; ++r) {
        if (std::system(command.c_str()) != 0) throw rtsdf::Error("'" + command + "' failed");
        nlohmann::json report = nlohmann::json::parse(std::ifstream(json));
        process.push_back(report["ms"]["process"].get<double>());
        openvdb.push_back(openvdb_build_ms(scene, rtsdf::fit_grid(gpu_scene.bounds(), resolution)));
      }
      std::printf("%5d: rtsdf sdf %.1f ms (ms.process), openvdb build %.1f ms, openvdb/rtsdf %.2f\n", resolution,
                  median(process), median(openvdb), median(openvdb) / median(process));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rtsdf_bench_coarse: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
