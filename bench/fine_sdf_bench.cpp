// Fine-SDF update speed against OpenVDB's narrow-band meshToLevelSet of the
// whole fine grid, in the same run: by fine resolution, rays per texel and
// triangle count. Medians over frames after one warm-up frame.
//
//   rtsdf_bench_fine [--frames N] [--quick] [--mesh PATH]
//
// --mesh adds a mesh of one's own (any format Assimp reads), e.g. a
// third-party CAD model, at the first case's settings.
//
// "bvh cost" is bvh_cost (the nodes' box areas over the root's, the SAH's
// measure) of one tree over every placed triangle: how many boxes a ray
// through the model meets, whatever the rays. A model of many nested,
// interpenetrating parts has a high one however its tree is built: its
// rays are slower for its geometry, not only for its tree.
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <string>

#include "bench_common.h"
#include "bvh.h"
#include "coarse_sdf.h"
#include "fine_sdf.h"
#include "mesh_import.h"
#include "vk/context.h"

namespace {

struct Case {
  std::string mesh;
  int fine_resolution;
  int rays;
  int interleave = 1;
};

}  // namespace

int main(int argc, char** argv) {
  int frames = 5;
  bool quick = false;
  std::string extra_mesh;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) frames = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--quick")) quick = true;
    else if (!std::strcmp(argv[i], "--mesh") && i + 1 < argc) extra_mesh = argv[++i];
    else {
      std::printf("usage: rtsdf_bench_fine [--frames N] [--quick] [--mesh PATH]\n");
      return std::strcmp(argv[i], "--help") ? 2 : 0;
    }
  }
  const std::string small = RTSDF_MESH_10K, medium = RTSDF_MESH_110K, large = RTSDF_MESH_1M;
  std::vector<Case> cases = {{medium, 128, 8}, {medium, 192, 8}, {medium, 256, 8},  // fine resolution
                             {medium, 128, 4}, {medium, 128, 16},                   // rays per texel
                             {small, 128, 8}, {large, 128, 8},                      // triangle count
                             {medium, 128, 8, 2}, {medium, 128, 8, 4}, {medium, 128, 8, 8}};  // interleave
  if (quick) cases = {{medium, 128, 8}, {small, 128, 8}, {medium, 128, 8, 4}};
  if (!extra_mesh.empty()) cases.push_back({extra_mesh, 128, 8});
  try {
    rtsdf::vk::Context context;
    std::printf("device %s; coarse 64, d = 2 coarse voxels, alpha 0.9; median of %d frames after one warm-up\n",
                context.info().name.c_str(), frames);
    std::printf("%9s %5s %5s %3s %12s %9s %9s %9s %10s %9s %9s %13s\n", "triangles", "fine", "rays", "K", "fine dims",
                "bvh ms", "bvh cost", "texels", "Mrays/s", "fine ms", "openvdb", "openvdb/fine");
    // Each mesh file's scene, loaded once for all its cases.
    struct Loaded {
      rtsdf::Scene scene;
      std::unique_ptr<rtsdf::GpuScene> gpu_scene;
      float bvh_cost = 0.0f;
    };
    std::map<std::string, Loaded> scenes;
    for (const Case& c : cases) {
      auto& [scene, gpu_scene, bvh_cost] = scenes[c.mesh];
      if (!gpu_scene) {
        scene = rtsdf::import_scene(c.mesh);
        gpu_scene = std::make_unique<rtsdf::GpuScene>(context, scene);
        bvh_cost = rtsdf::bvh_cost(rtsdf::build_mesh_bvh(rtsdf::placed_mesh(scene)));
      }
      rtsdf::CoarseSdf coarse(context);
      coarse.build(*gpu_scene, rtsdf::fit_grid(gpu_scene->bounds(), 64), 0.5f);
      rtsdf::FineSdf fine(context);
      const rtsdf::GridSpec grid = rtsdf::FineSdf::fit(coarse.grid(), c.fine_resolution);
      rtsdf::FineTraceSettings settings;
      settings.rays_per_texel = c.rays;
      settings.interleave = c.interleave;
      fine.update(*gpu_scene, coarse, grid, settings);
      std::vector<double> ms;
      for (int f = 0; f < frames; ++f) {
        fine.update(*gpu_scene, coarse, grid, settings);
        ms.push_back(fine.last_frame().total_ms());
      }
      const double fine_ms = rtsdf::bench::median(ms);
      const uint32_t texels = fine.read_traced_texels();
      const double vdb_ms = rtsdf::bench::openvdb_build_ms(scene, grid);
      char dims[32];
      std::snprintf(dims, sizeof dims, "%dx%dx%d", grid.dims.x, grid.dims.y, grid.dims.z);
      std::printf("%9zu %5d %5d %3d %12s %9.1f %9.1f %9u %10.2f %9.1f %9.1f %13.2f\n", scene.triangle_count(),
                  c.fine_resolution, c.rays, c.interleave, dims, gpu_scene->bvh_build_ms(), bvh_cost, texels,
                  double(texels) * c.rays / (fine_ms * 1e3), fine_ms, vdb_ms, vdb_ms / fine_ms);
    }
    std::printf("K = interleave: each band texel traced every K-th frame.\n"
                "fine ms = one fine update (classify + trace of the band); openvdb = narrow-band meshToLevelSet\n"
                "(half width 3) of the same fine grid; openvdb/fine > 1 means one update was faster.\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rtsdf_bench_fine: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
