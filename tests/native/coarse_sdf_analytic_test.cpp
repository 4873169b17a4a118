// The coarse SDF of shapes whose exact distance is known.
#include <cmath>
#include <functional>
#include <limits>
#include <glm/gtc/matrix_transform.hpp>

#include "coarse_sdf.h"
#include "reference/exact.h"
#include "reference/shapes.h"
#include "shaders/shared.h"
#include "vulkan_test.h"

namespace rtsdf {
namespace {

using reference::CoarseErrors;

struct Built {
  GridSpec grid;
  std::vector<float> distance;
  std::vector<uint32_t> seeds;
  float beta_world;
};

class CoarseSdfAnalytic : public testing::VulkanTest {
 protected:
  Built build(const Scene& scene, int resolution, float beta = 0.5f) {
    GpuScene gpu_scene(context(), scene);
    CoarseSdf coarse(context());
    GridSpec grid = fit_grid(gpu_scene.bounds(), resolution);
    coarse.build(gpu_scene, grid, beta);
    return {grid, coarse.read_distance(), coarse.read_seeds(), coarse.beta_world()};
  }

  // Mean and max of |coarse + beta - |exact|| in voxels over voxels with |exact| <= band.
  static std::pair<double, double> errors(const Built& b, const std::function<float(glm::vec3)>& exact, float band) {
    double sum = 0, worst = 0;
    size_t count = 0;
    for (int z = 0; z < b.grid.dims.z; ++z)
      for (int y = 0; y < b.grid.dims.y; ++y)
        for (int x = 0; x < b.grid.dims.x; ++x) {
          float e = std::abs(exact(b.grid.voxel_center({x, y, z}))) / b.grid.voxel_size;
          if (e > band) continue;
          size_t i = size_t(x) + size_t(b.grid.dims.x) * (y + size_t(b.grid.dims.y) * z);
          double error = std::abs((b.distance[i] + b.beta_world) / b.grid.voxel_size - e);
          sum += error, worst = std::max(worst, error), count++;
        }
    EXPECT_GT(count, 0u);
    return {sum / double(count), worst};
  }
};

TEST_F(CoarseSdfAnalytic, SphereMatchesExactDistance) {
  const glm::vec3 center(0.1f, -0.2f, 0.3f);
  const float radius = 0.8f;
  Built b = build(single_mesh_scene(reference::uv_sphere(center, radius, 256)), 64);
  auto [mean, worst] = errors(b, [&](glm::vec3 p) { return glm::length(p - center) - radius; }, 3.0f);
  std::printf("sphere 64: mean %.3f max %.3f voxels\n", mean, worst);
  EXPECT_LT(mean, 0.5);
  EXPECT_LT(worst, 1.0);
  // Far from the surface jump flooding still finds the nearest surface voxel.
  auto far = errors(b, [&](glm::vec3 p) { return glm::length(p - center) - radius; }, 1e9f);
  EXPECT_LT(far.second, 1.2);
}

TEST_F(CoarseSdfAnalytic, BoxMatchesExactDistance) {
  const glm::vec3 lo(-1.0f, -0.5f, -0.25f), hi(1.0f, 0.5f, 0.25f);
  Built b = build(single_mesh_scene(reference::box(lo, hi)), 64);
  auto [mean, worst] = errors(b, [&](glm::vec3 p) { return reference::box_distance(p, lo, hi); }, 3.0f);
  std::printf("box 64: mean %.3f max %.3f voxels\n", mean, worst);
  EXPECT_LT(mean, 0.5);
  EXPECT_LT(worst, 1.0);
}

TEST_F(CoarseSdfAnalytic, ThinPlateHasNoGapAndMatchesDistance) {
  // 0.002 thick against voxels of ~0.03: far thinner than a voxel.
  const glm::vec3 lo(-1.0f, -1.0f, -0.001f), hi(1.0f, 1.0f, 0.001f);
  Scene scene = single_mesh_scene(reference::box(lo, hi));
  scene.instances[0].object_to_world = glm::mat4(glm::mat3(glm::rotate(glm::mat4(1.0f), 0.4f, glm::vec3(1, 1, 0))));
  Built b = build(scene, 64);
  const glm::mat4 to_object = glm::inverse(scene.instances[0].object_to_world);
  auto exact = [&](glm::vec3 p) { return reference::box_distance(glm::vec3(to_object * glm::vec4(p, 1)), lo, hi); };
  auto [mean, worst] = errors(b, exact, 3.0f);
  std::printf("thin plate 64: mean %.3f max %.3f voxels\n", mean, worst);
  EXPECT_LT(mean, 0.5);
  EXPECT_LT(worst, 1.0);
  // The plate is inside the coarse surface (coarse <= 0) wherever it passes.
  std::vector<uint8_t> surface = reference::surface_voxels(scene, b.grid);
  for (size_t i = 0; i < surface.size(); ++i)
    if (surface[i]) ASSERT_LE(b.distance[i], 0.0f) << "voxel " << i;
}

TEST_F(CoarseSdfAnalytic, TinyTriangleIsSeededAndDistanceIsRadial) {
  // A triangle far smaller than a voxel, in a grid fitted to a larger scene.
  Mesh mesh = reference::single_triangle({0.01f, 0.02f, 0.03f}, {0.012f, 0.02f, 0.03f}, {0.01f, 0.021f, 0.031f});
  reference::append(mesh, reference::box({-1, -1, -1}, {-0.9f, -0.9f, -0.9f}));
  Scene scene = single_mesh_scene(mesh);
  Built b = build(scene, 32);
  std::vector<uint8_t> surface = reference::surface_voxels(scene, b.grid);
  size_t missing = 0, marked = 0;
  for (size_t i = 0; i < surface.size(); ++i) {
    marked += surface[i];
    missing += surface[i] && b.seeds[i] == gpu::kNoSeed;
  }
  EXPECT_GT(marked, 0u);
  EXPECT_EQ(missing, 0u);
  const glm::vec3 tip(0.01f, 0.02f, 0.03f);
  auto [mean, worst] = errors(b, [&](glm::vec3 p) { return std::min(glm::length(p - tip),
      reference::box_distance(p, {-1, -1, -1}, {-0.9f, -0.9f, -0.9f})); }, 3.0f);
  std::printf("tiny triangle 32: mean %.3f max %.3f voxels\n", mean, worst);
  EXPECT_LT(worst, 1.0);
}

TEST_F(CoarseSdfAnalytic, VoxelizationIsExactlyTheOverlappedVoxels) {
  // Thin slivers, a sub-voxel triangle and grazing planes: every overlapped
  // voxel is a seed (no holes) and nothing beyond a hair's tolerance is.
  Mesh mesh = reference::uv_sphere({0, 0, 0}, 0.7f, 96);
  reference::append(mesh, reference::single_triangle({-0.9f, -0.9f, 0.0f}, {0.9f, -0.88f, 0.001f}, {0.9f, -0.9f, 0.0f}));
  reference::append(mesh, reference::single_triangle({0.5f, 0.8f, 0.5f}, {0.503f, 0.8f, 0.5f}, {0.5f, 0.802f, 0.5f}));
  reference::append(mesh, reference::sheet({-0.9f, 0.75f}, {0.9f, 0.95f}, 0.3333f));
  Scene scene = single_mesh_scene(mesh);
  Built b = build(scene, 48);
  std::vector<uint8_t> must = reference::surface_voxels(scene, b.grid, 0.0);
  std::vector<uint8_t> may = reference::surface_voxels(scene, b.grid, 1e-3);
  size_t holes = 0, extra = 0, seeds = 0;
  for (size_t i = 0; i < must.size(); ++i) {
    bool seeded = b.seeds[i] != gpu::kNoSeed;
    seeds += seeded;
    holes += must[i] && !seeded;
    if (must[i] && !seeded && holes <= 3) {
      int x = int(i % b.grid.dims.x), y = int(i / b.grid.dims.x % b.grid.dims.y), z = int(i / b.grid.dims.x / b.grid.dims.y);
      glm::vec3 c = b.grid.voxel_center({x, y, z});
      std::printf("hole at voxel %d %d %d world %.3f %.3f %.3f\n", x, y, z, c.x, c.y, c.z);
    }
    extra += seeded && !may[i];
  }
  std::printf("voxelization 48: %zu seeds, %zu holes, %zu extra\n", seeds, holes, extra);
  EXPECT_GT(seeds, 100u);
  EXPECT_EQ(holes, 0u);
  EXPECT_EQ(extra, 0u);
}

TEST_F(CoarseSdfAnalytic, AMeshFieldIsTheExactDistanceToTheNearestSeed) {
  // A mesh's own field (build_mesh: the exact transform) against the nearest
  // seed found by brute force, and against the jump flood of the same seeds
  // (build: the whole scene's field), which may miss the nearest seed but
  // never finds one nearer than there is. A sphere, slivers and a sheet
  // leave lines of the grid with no seed, one seed and many. The grids' long
  // axes fill the pipeline's lines (32) or not (40 of 64).
  Mesh mesh = reference::uv_sphere({0.2f, 0, 0}, 0.5f, 64);
  reference::append(mesh, reference::single_triangle({-0.9f, -0.9f, 0.0f}, {0.9f, -0.88f, 0.001f}, {0.9f, -0.9f, 0.0f}));
  reference::append(mesh, reference::sheet({-0.9f, 0.75f}, {0.9f, 0.95f}, 0.3333f));
  Scene scene = single_mesh_scene(mesh);
  GpuScene gpu_scene(context(), scene);
  for (int resolution : {32, 40}) {
    const GridSpec grid = fit_grid(gpu_scene.bounds(), resolution);
    const float beta = 0.5f;
    CoarseSdf flood(context()), exact(context());
    flood.build(gpu_scene, grid, beta);
    exact.build_mesh(gpu_scene, 0, grid, beta);
    const std::vector<uint32_t> seeds = exact.read_seeds();
    ASSERT_EQ(seeds, flood.read_seeds());
    std::vector<glm::ivec3> seeded;
    for (int z = 0; z < grid.dims.z; ++z)
      for (int y = 0; y < grid.dims.y; ++y)
        for (int x = 0; x < grid.dims.x; ++x)
          if (seeds[size_t(x) + size_t(grid.dims.x) * (y + size_t(grid.dims.y) * z)] != gpu::kNoSeed)
            seeded.push_back({x, y, z});
    ASSERT_GT(seeded.size(), 100u);
    const std::vector<float> exact_distance = exact.read_distance(), flood_distance = flood.read_distance();
    size_t wrong = 0, flood_misses = 0, flood_nearer = 0;
    for (int z = 0; z < grid.dims.z; ++z)
      for (int y = 0; y < grid.dims.y; ++y)
        for (int x = 0; x < grid.dims.x; ++x) {
          int nearest = std::numeric_limits<int>::max();
          for (const glm::ivec3& s : seeded) {
            const glm::ivec3 d = s - glm::ivec3(x, y, z);
            nearest = std::min(nearest, d.x * d.x + d.y * d.y + d.z * d.z);
          }
          const float expected = std::sqrt(float(nearest)) * grid.voxel_size - beta * grid.voxel_size;
          const size_t i = size_t(x) + size_t(grid.dims.x) * (y + size_t(grid.dims.y) * z);
          wrong += std::abs(exact_distance[i] - expected) > 1e-5f * grid.voxel_size * float(grid.dims.x);
          flood_misses += flood_distance[i] > exact_distance[i] + 1e-4f * grid.voxel_size;
          flood_nearer += flood_distance[i] < exact_distance[i] - 1e-4f * grid.voxel_size;
        }
    std::printf("exact distance %dx%dx%d: %zu seeds, %zu voxels wrong; the flood missed the nearest seed at %zu\n",
                grid.dims.x, grid.dims.y, grid.dims.z, seeded.size(), wrong, flood_misses);
    EXPECT_EQ(wrong, 0u);
    EXPECT_EQ(flood_nearer, 0u);
    EXPECT_GT(exact.timings().exact_distance_ms, 0.0);
  }
}

TEST_F(CoarseSdfAnalytic, BetaShiftsTheFieldAndMakesSurfaceVoxelsNegative) {
  Scene scene = single_mesh_scene(reference::box({-1, -1, -1}, {1, 1, 1}));
  Built a = build(scene, 32, 0.0f);
  Built b = build(scene, 32, 1.0f);
  ASSERT_EQ(a.distance.size(), b.distance.size());
  for (size_t i = 0; i < a.distance.size(); i += 97)
    ASSERT_NEAR(a.distance[i] - b.distance[i], b.grid.voxel_size, 1e-5f);
  size_t negative = 0;
  for (float d : b.distance) negative += d < 0.0f;
  EXPECT_GT(negative, 0u);
}

}  // namespace
}  // namespace rtsdf
