// rtsdf: command-line front end of the native core.
//   rtsdf sdf MESH --coarse-res N [--beta B] --out FILE.vdb [--json FILE]
//   rtsdf devices
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include <algorithm>

#include "coarse_sdf.h"
#include "fine_sdf.h"
#include "mesh_import.h"
#include "vdb_export.h"
#include "version.h"
#include "vk/context.h"

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The command bakes a static mesh over --frames frames. Tracing each band
// texel every 4th frame costs a quarter per frame and, measured on the sample
// (docs/algorithm.md), ends 32 frames both sooner in total and closer to the exact
// distance than tracing every frame; its only cost, forgetting a moved
// surface 4x slower, does not arise for a static mesh.
rtsdf::FineTraceSettings static_bake_settings() {
  rtsdf::FineTraceSettings settings;
  settings.interleave = 4;
  return settings;
}

struct SdfOptions {
  std::string mesh;
  int coarse_resolution = 64;
  float beta = 0.5f;
  std::string out;
  std::string json;
  std::string device;
  int fine_resolution = 0;  // 0: coarse only
  int frames = 32;
  rtsdf::FineTraceSettings fine = static_bake_settings();
};

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

int run_sdf(const SdfOptions& options) {
  const Clock::time_point start = Clock::now();
  rtsdf::Scene scene = rtsdf::import_scene(options.mesh);
  scene.validate();
  const rtsdf::GridSpec grid = rtsdf::fit_grid(scene.world_bounds(), options.coarse_resolution);
  const double load_ms = ms_since(start);

  Clock::time_point step = Clock::now();
  rtsdf::vk::ContextOptions context_options = rtsdf::vk::ContextOptions::from_environment();
  if (!options.device.empty()) context_options.device_name = options.device;
  rtsdf::vk::Context context(context_options);
  rtsdf::CoarseSdf coarse(context);
  const double device_ms = ms_since(step);

  step = Clock::now();
  rtsdf::GpuScene gpu_scene(context, scene);
  const double upload_ms = ms_since(step);

  step = Clock::now();
  coarse.build(gpu_scene, grid, options.beta);
  const double build_ms = ms_since(step);

  // The fine SDF accumulates over frames of a static scene: the coarse SDF
  // and the BVH are built once, the band is traced every frame.
  rtsdf::FineSdf fine(context);
  rtsdf::GridSpec fine_grid;
  std::vector<double> fine_frame_ms;
  uint32_t texels_traced = 0;
  if (options.fine_resolution > 0) {
    fine_grid = rtsdf::FineSdf::fit(grid, options.fine_resolution);
    for (int frame = 0; frame < options.frames; ++frame) {
      fine.update(gpu_scene, coarse, fine_grid, options.fine);
      fine_frame_ms.push_back(fine.last_frame().total_ms());
    }
    texels_traced = fine.read_traced_texels();
  }

  step = Clock::now();
  std::vector<float> distance = coarse.read_distance();
  std::vector<float> fine_distance;
  if (options.fine_resolution > 0) fine_distance = fine.read_distance();
  const double readback_ms = ms_since(step);

  step = Clock::now();
  std::vector<rtsdf::NamedField> fields{{"coarse", grid, &distance}};
  if (options.fine_resolution > 0) fields.push_back({"fine", fine_grid, &fine_distance});
  rtsdf::write_vdb(options.out, fields);
  const double write_ms = ms_since(step);

  const rtsdf::CoarseSdfTimings& t = coarse.timings();
  nlohmann::json report = {
      {"device", context.info().name},
      {"device_type", context.info().type},
      {"mesh", options.mesh},
      {"triangles", scene.triangle_count()},
      {"coarse_resolution", options.coarse_resolution},
      {"voxel_size", grid.voxel_size},
      {"dims", {grid.dims.x, grid.dims.y, grid.dims.z}},
      {"origin", {grid.origin.x, grid.origin.y, grid.origin.z}},
      {"beta", coarse.beta_world()},
      {"beta_voxels", options.beta},
      {"jump_flood_steps", rtsdf::JumpFloodPass::steps(grid.dims)},
      {"ms",
       {{"voxelize", t.voxelize_ms},
        {"jump_flood", t.jump_flood_ms},
        {"jump_flood_passes", t.pass_ms},
        {"total", build_ms},
        {"load", load_ms},
        {"device_init", device_ms},
        {"upload", upload_ms},
        {"readback", readback_ms},
        {"write", write_ms},
        {"process", ms_since(start)}}},
  };
  if (options.fine_resolution > 0) {
    report["fine_resolution"] = options.fine_resolution;
    report["fine_dims"] = {fine_grid.dims.x, fine_grid.dims.y, fine_grid.dims.z};
    report["fine_voxel_size"] = fine_grid.voxel_size;
    report["frames"] = options.frames;
    report["d"] = options.fine.trace_band;
    report["d_world"] = options.fine.trace_band * grid.voxel_size;
    report["alpha"] = options.fine.decay;
    report["rays_per_texel"] = options.fine.rays_per_texel;
    report["interleave"] = options.fine.interleave;
    report["texels_traced"] = texels_traced;
    report["rays_per_frame"] = uint64_t(texels_traced) * uint64_t(options.fine.rays_per_texel);
    report["ms"]["fine_trace"] = median(fine_frame_ms);
    report["ms"]["fine_frames"] = fine_frame_ms;
    report["ms"]["bvh_build"] = gpu_scene.bvh_build_ms();
    const double trace_s = median(fine_frame_ms) * 1e-3;
    report["rays_per_second"] = trace_s > 0 ? double(texels_traced) * options.fine.rays_per_texel / trace_s : 0.0;
  }
  if (context.validation_message_count() > 0) report["validation_messages"] = context.validation_message_count();
  if (!options.json.empty()) {
    std::ofstream file(options.json);
    if (!(file << report.dump(2) << "\n")) throw rtsdf::Error("cannot write '" + options.json + "'");
  }
  std::printf("%s: %zu triangles, %dx%dx%d voxels of %.5g, voxelize %.1f ms, jump flood %.1f ms, total %.1f ms -> %s\n",
              context.info().name.c_str(), scene.triangle_count(), grid.dims.x, grid.dims.y, grid.dims.z,
              grid.voxel_size, t.voxelize_ms, t.jump_flood_ms, build_ms, options.out.c_str());
  return 0;
}

int run_devices() {
  for (const rtsdf::vk::DeviceInfo& d : rtsdf::vk::Context::list_devices())
    std::printf("%s (%s, Vulkan %s, %s)\n", d.name.c_str(), d.type.c_str(), d.api_version.c_str(), d.driver.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"RTSDF: signed distance fields of whole scenes on the Vulkan device, for soft shadows.\n"
               "Environment: RTSDF_DEVICE=NAME picks a Vulkan device by (part of) its name;\n"
               "RTSDF_VALIDATION=1 turns on the Khronos validation layer.",
               "rtsdf"};
  app.set_version_flag("--version", std::string(rtsdf::kVersion));
  app.require_subcommand(1);

  SdfOptions sdf;
  CLI::App* sdf_cmd = app.add_subcommand("sdf", "Compute the coarse SDF of a mesh file and write it as OpenVDB.");
  sdf_cmd->add_option("MESH", sdf.mesh, "Mesh file: anything Assimp reads (OBJ, PLY, glTF/GLB, STL, FBX, ...); "
                                        "node transforms are applied")
      ->required();
  sdf_cmd->add_option("--coarse-res", sdf.coarse_resolution,
                      "Voxels on the longest axis of the coarse grid, 4 to 1024 (the grid is the scene's bounds "
                      "plus a margin of 3 voxels, cubic voxels)")
      ->capture_default_str();
  sdf_cmd->add_option("--beta", sdf.beta,
                      "Bias subtracted from the coarse distance, in coarse voxels: surfaces thicken by beta and get "
                      "a negative inside (the JSON reports it in world units)")
      ->capture_default_str();
  sdf_cmd->add_option("--out", sdf.out, "Output .vdb: a level-set FloatGrid 'coarse', world units, negative inside")
      ->required();
  sdf_cmd->add_option("--json", sdf.json,
                      "Also write figures as JSON: device, triangles, voxel_size, dims, beta (world units) and ms "
                      "{voxelize, jump_flood (GPU time), total (SDF build wall time), process (whole run)}");
  sdf_cmd->add_option("--device", sdf.device, "Vulkan device name (substring); overrides RTSDF_DEVICE");
  sdf_cmd->add_option("--fine-res", sdf.fine_resolution,
                      "Also compute the fine SDF: voxels on the longest axis over the same bounds (at least the "
                      "coarse resolution, at most 1024); written as grid 'fine'");
  sdf_cmd->add_option("--frames", sdf.frames, "Fine-SDF frames to accumulate (static scene)")->capture_default_str();
  sdf_cmd->add_option("--d", sdf.fine.trace_band,
                      "Trace band d in coarse voxels: fine texels with coarse distance <= d are ray traced")
      ->capture_default_str();
  sdf_cmd->add_option("--alpha", sdf.fine.decay, "Decay alpha: weight of the previous frame's distance to thin pieces' slabs, in [0, 1) (other texels keep their nearest triangle)")
      ->capture_default_str();
  sdf_cmd->add_option("--rays", sdf.fine.rays_per_texel, "Rays per traced texel per frame")->capture_default_str();
  sdf_cmd->add_option("--interleave", sdf.fine.interleave,
                      "Trace each band texel every K-th frame (1 to 64): K times less work per frame, K times more "
                      "frames to converge and to forget a moved surface (1 = every frame, as in the paper)")
      ->capture_default_str();

  app.add_subcommand("devices", "List the Vulkan devices the loader sees.");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "rtsdf: error: %s (see rtsdf --help)\n", e.what());
    return 2;
  }

  try {
    if (app.got_subcommand("devices")) return run_devices();
    if (!std::isfinite(sdf.beta) || sdf.beta < 0.0f || sdf.beta > 16.0f)
      throw rtsdf::Error("--beta must be between 0 and 16 coarse voxels");
    if (sdf.frames < 1 || sdf.frames > 100000) throw rtsdf::Error("--frames must be 1 to 100000");
    return run_sdf(sdf);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rtsdf: error: %s\n", e.what());
    return 1;
  }
}
