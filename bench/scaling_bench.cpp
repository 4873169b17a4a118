// How the object-space design scales, each figure against its own base case
// in the same run:
// - instances: N copies of one mesh scattered over a ground (one field
//   however many there are): upload ("sync", the GpuScene), the fields
//   (begin), and the first frame (G-buffer and shading), against N = 1;
// - triangles: one mesh of 10K, 110K or 1M triangles moved rigidly on a
//   ground, its field refined: the cost of a frame after a move, against 10K.
// Sample meshes as the fine-SDF benchmark's.
//
//   rtsdf_bench_scaling [--instances N,N,...] [--frames N]
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "bench_common.h"
#include "error.h"
#include "mesh_import.h"
#include "renderer.h"
#include "vk/context.h"

namespace {

using namespace rtsdf;

constexpr int kSize = 256;  // pixels of the image rendered, both ways

Mesh ground(float half) {
  Mesh mesh;
  mesh.name = "ground";
  mesh.positions = {{-half, -half, 0}, {half, -half, 0}, {half, half, 0}, {-half, half, 0}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  return mesh;
}

// `mesh` fitted into a unit cube resting on z = 0 (object space), so that
// every sample mesh is placed alike.
Mesh unit_sized(Mesh mesh) {
  Bounds b{glm::vec3(1e30f), glm::vec3(-1e30f)};
  for (const glm::vec3& p : mesh.positions) b.lo = glm::min(b.lo, p), b.hi = glm::max(b.hi, p);
  const glm::vec3 e = b.extent();
  const float s = 1.0f / std::max(e.x, std::max(e.y, e.z));
  const glm::vec3 centre = 0.5f * (b.lo + b.hi);
  for (glm::vec3& p : mesh.positions) p = (p - glm::vec3(centre.x, centre.y, b.lo.z)) * s;
  return mesh;
}

Mesh load_mesh(const std::string& path) {
  Scene scene = import_scene(path);
  return unit_sized(scene.meshes.at(0));
}

Camera view_from_above(float half) {
  Camera camera;
  camera.world_to_view = glm::lookAt(glm::vec3(0.3f * half, -0.6f * half, 1.2f * half), glm::vec3(0), glm::vec3(0, 0, 1));
  camera.projection = glm::perspective(glm::radians(60.0f), 1.0f, 0.05f, 10.0f * half);
  return camera;
}

Light sun() {
  Light light;
  light.direction = glm::normalize(glm::vec3(0.4f, 0.3f, -1.0f));
  light.energy = 3.0f;
  light.sun_angle = glm::radians(2.0f);
  return light;
}

RenderSettings viewport_like() {
  RenderSettings settings;
  settings.samples = 64;
  settings.sdf_updates = 0;  // the viewport's: refine until converged, then stop
  settings.keep_history = true;
  return settings;
}

// N instances of `mesh` on a square grid two units apart, over a ground.
Scene scattered(const Mesh& mesh, int n) {
  Scene scene;
  const int side = int(std::ceil(std::sqrt(double(n))));
  const float half = float(side);
  scene.meshes = {mesh, ground(half + 1.0f)};
  for (int i = 0; i < n; ++i) {
    const glm::vec3 at(-half + 1.0f + 2.0f * float(i % side), -half + 1.0f + 2.0f * float(i / side), 0.0f);
    scene.instances.push_back({0, glm::rotate(glm::translate(glm::mat4(1.0f), at), 0.7f * float(i), {0, 0, 1})});
  }
  scene.instances.push_back({1, glm::mat4(1.0f)});
  return scene;
}

void instances(vk::Context& context, const Mesh& mesh, const std::vector<int>& counts) {
  std::printf("\ninstances of one %zu-triangle mesh (%dx%d, viewport settings): ms, and ratio to 1 instance\n",
              mesh.indices.size() / 3, kSize, kSize);
  std::printf("%9s %7s %9s %9s %9s %9s %9s %9s %11s\n", "instances", "fields", "placed", "sync", "fields", "frame",
              "total", "x one", "triangles");
  double one = 0.0;
  for (int n : counts) {
    try {
      const Scene scene = scattered(mesh, n);
      const float half = float(std::ceil(std::sqrt(double(n)))) + 1.0f;
      std::unique_ptr<GpuScene> gpu_scene;
      Renderer renderer(context);
      const double sync_ms = bench::time_ms([&] { gpu_scene = std::make_unique<GpuScene>(context, scene); });
      const double begin_ms = bench::time_ms([&] {
        renderer.begin(*gpu_scene, view_from_above(half), {sun()}, glm::vec3(0.05f), kSize, kSize, viewport_like(), true);
      });
      const double frame_ms = bench::time_ms([&] {
        renderer.add_frame();
        renderer.read(false);
      });
      const RenderStats stats = renderer.read(false).stats;
      const double total = sync_ms + begin_ms + frame_ms;
      if (one == 0.0) one = total;
      std::printf("%9d %7d %9d %9.1f %9.1f %9.1f %9.1f %9.2f %11zu\n", n, stats.fields, stats.field_instances, sync_ms,
                  begin_ms, frame_ms, total, total / one, size_t(n) * (mesh.indices.size() / 3));
    } catch (const Error& e) {
      std::printf("%9d  error: %s\n", n, e.what());
    }
  }
}

void triangles(vk::Context& context, const std::vector<std::pair<std::string, Mesh>>& meshes, int frames) {
  std::printf("\none mesh moved rigidly on a ground, its field refined (%dx%d, viewport settings): median of %d moves\n",
              kSize, kSize, frames);
  std::printf("%5s %10s %10s %11s %9s %7s %8s\n", "mesh", "triangles", "refine ms", "traced", "frame ms", "x 10K",
              "field MB");
  double base = 0.0;
  for (const auto& [name, mesh] : meshes) {
    const Scene scene = scattered(mesh, 1);
    GpuScene gpu_scene(context, scene);
    Renderer renderer(context);
    const Camera camera = view_from_above(2.0f);
    const RenderSettings settings = viewport_like();
    const double refine_ms = bench::time_ms([&] {
      renderer.begin(gpu_scene, camera, {sun()}, glm::vec3(0.05f), kSize, kSize, settings, true);
      while (renderer.refining()) renderer.add_frame();
    });
    std::vector<double> times;
    std::vector<glm::mat4> transforms = {scene.instances[0].object_to_world, scene.instances[1].object_to_world};
    uint64_t traced = 0;
    for (int f = 0; f < frames; ++f) {
      transforms[0] = glm::rotate(glm::translate(glm::mat4(1.0f), {0.1f * float(f % 3), 0, 0}), 0.2f * float(f), {0, 0, 1});
      times.push_back(bench::time_ms([&] {
        gpu_scene.set_transforms(transforms);
        renderer.begin(gpu_scene, camera, {sun()}, glm::vec3(0.05f), kSize, kSize, settings, true);
        renderer.add_frame();
        renderer.read(false);
      }));
      traced += renderer.stats().last_frame_traced_texels;
    }
    const double frame = bench::median(times);
    if (base == 0.0) base = frame;
    const RenderStats stats = renderer.read(false).stats;
    std::printf("%5s %10zu %10.0f %11llu %9.1f %7.2f %8.1f\n", name.c_str(), mesh.indices.size() / 3, refine_ms,
                (unsigned long long)traced, frame, frame / base, stats.field_mb);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> counts = {1, 10, 100, 1000, 10000, 100000};
  int frames = 7;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--instances") && i + 1 < argc) {
      counts.clear();
      std::stringstream list(argv[++i]);
      for (std::string item; std::getline(list, item, ',');) counts.push_back(std::max(1, std::atoi(item.c_str())));
    } else if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) {
      frames = std::max(1, std::atoi(argv[++i]));
    } else {
      std::printf("usage: rtsdf_bench_scaling [--instances N,N,...] [--frames N]\n");
      return std::strcmp(argv[i], "--help") ? 2 : 0;
    }
  }
  try {
    vk::Context context;
    std::printf("device %s\n", context.info().name.c_str());
    const Mesh small = load_mesh(RTSDF_MESH_10K);
    instances(context, small, counts);
    triangles(context, {{"10K", small}, {"110K", load_mesh(RTSDF_MESH_110K)}, {"1M", load_mesh(RTSDF_MESH_1M)}},
              frames);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rtsdf_bench_scaling: %s\n", e.what());
    return 1;
  }
  return 0;
}
