// The fine SDF: accuracy against OpenVDB on a real mesh, thin plates, sign
// inside closed meshes, and recovery after an object moves away.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <glm/gtc/matrix_transform.hpp>

#include "coarse_sdf.h"
#include "fine_sdf.h"
#include "mesh_import.h"
#include "object_fields.h"
#include "reference/exact.h"
#include "reference/shapes.h"
#include "vulkan_test.h"

namespace rtsdf {
namespace {

// Voxels a triangle passes through where the field claims no surface within
// the voxel (|fine| above half its diagonal), as a share of such voxels.
// Share of the voxels a triangle passes through that the fine SDF reads as
// clear of surfaces (above half a voxel diagonal): gaps a shadow ray could
// slip through. Voxels reading well inside (thin pieces read as slabs one
// voxel thick, see fine_trace.comp) are counted apart: they block rays.
double hole_share(const Scene& scene, const GridSpec& grid, const std::vector<float>& fine) {
  std::vector<uint8_t> surface = reference::surface_voxels(scene, grid);
  const float half_diagonal = 0.5f * std::sqrt(3.0f) * grid.voxel_size;
  size_t surface_count = 0, holes = 0, deep = 0;
  for (size_t i = 0; i < surface.size(); ++i)
    if (surface[i]) surface_count++, holes += fine[i] > half_diagonal, deep += fine[i] < -half_diagonal;
  std::printf("fine holes: %zu of %zu surface voxels (%.3f%%); %zu read deeper inside than half a voxel diagonal\n",
              holes, surface_count, 100.0 * double(holes) / double(surface_count), deep);
  return double(holes) / double(surface_count);
}

class FineSdfTest : public testing::VulkanTest {
 protected:
  struct Built {
    GridSpec grid;
    std::vector<float> fine;
    uint32_t traced;
  };
  Built build(GpuScene& scene, int coarse_res, int fine_res, int frames, FineTraceSettings settings = {}) {
    CoarseSdf coarse(context());
    coarse.build(scene, fit_grid(scene.bounds(), coarse_res), 0.5f);
    FineSdf fine(context());
    GridSpec grid = FineSdf::fit(coarse.grid(), fine_res);
    for (int f = 0; f < frames; ++f) fine.update(scene, coarse, grid, settings);
    return {grid, fine.read_distance(), fine.read_traced_texels()};
  }
};

TEST_F(FineSdfTest, RealMeshConvergesTowardsOpenVdb) {
  const std::string path = testing::test_mesh_path();
  Scene scene = import_scene(path);
  GpuScene gpu_scene(context(), scene);
  std::vector<float> exact;
  double previous = 1e9;
  for (int frames : {1, 8, 32}) {
    Built b = build(gpu_scene, 64, 128, frames);
    if (exact.empty()) exact = reference::signed_distance(scene, b.grid, 3.0f);
    reference::FineErrors e = reference::compare_fine(b.fine, exact, b.grid, 2.0f);
    std::printf("%s 64/128 after %d frames: mean |fine-exact| %.3f fine voxels over %zu, wrong signs %.2f%%, "
                "%u texels traced\n", path.c_str(), frames, e.mean_abs_voxels, e.band_voxels,
                100.0 * e.wrong_sign_share, b.traced);
    EXPECT_LE(e.mean_abs_voxels, previous + 0.02) << "more frames must not make it worse";
    previous = e.mean_abs_voxels;
    if (frames == 32) {
      EXPECT_LE(e.mean_abs_voxels, 0.35);
      EXPECT_LE(e.wrong_sign_share, 0.03);
      EXPECT_LT(hole_share(scene, b.grid, b.fine), 0.01);
    }
  }
}

TEST_F(FineSdfTest, InterleavedTracingStillConvergesAndTracesAShare) {
  Scene scene = import_scene(testing::test_mesh_path());
  GpuScene gpu_scene(context(), scene);
  FineTraceSettings every_frame, interleaved;
  interleaved.interleave = 4;
  Built full = build(gpu_scene, 64, 128, 1, every_frame);
  Built quarter = build(gpu_scene, 64, 128, 32, interleaved);
  // One frame in four traces about a quarter of the band.
  EXPECT_NEAR(double(quarter.traced) / double(full.traced), 0.25, 0.02);
  reference::FineErrors e =
      reference::compare_fine(quarter.fine, reference::signed_distance(scene, quarter.grid, 3.0f), quarter.grid, 2.0f);
  std::printf("interleave 4, 32 frames: mean |fine-exact| %.3f fine voxels, wrong signs %.2f%%, %u of %u texels per "
              "frame\n", e.mean_abs_voxels, 100.0 * e.wrong_sign_share, quarter.traced, full.traced);
  EXPECT_LE(e.mean_abs_voxels, 0.35);
  EXPECT_LE(e.wrong_sign_share, 0.03);
  EXPECT_LT(hole_share(scene, quarter.grid, quarter.fine), 0.01);
}

// A still field retraces, after its first two updates, only the texels
// still improving: on a CAD part and on a third-party model (open,
// overlapping parts) four updates take at most 60% of the rays of four full
// ones, and the last lists under a twentieth as many texels. What that
// costs the field is printed (how much it costs the shadows is
// ObjectFieldsTest.SkippingConvergedTexelsKeepsTheShadows's question).
TEST_F(FineSdfTest, AStillFieldRetracesOnlyTheTexelsStillImproving) {
  for (const std::string& path :
       {testing::test_mesh_path(), std::string(RTSDF_THIRD_PARTY_MODELS) + "/OBJ/spider.obj"}) {
    Scene scene = import_scene(path);
    GpuScene gpu_scene(context(), scene);
    CoarseSdf coarse(context());
    coarse.build(gpu_scene, fit_grid(gpu_scene.bounds(), 64), 0.5f);
    const GridSpec grid = FineSdf::fit(coarse.grid(), 128);
    const std::vector<float> exact = reference::signed_distance(scene, grid, 3.0f);
    struct Outcome {
      double mean_abs_voxels;
      uint64_t traced;
      uint32_t second_traced, last_traced;
    };
    auto run = [&](bool skip_converged) {
      FineTraceSettings settings;  // (the paper's decay, as in the object fields)
      settings.skip_converged = skip_converged;
      FineSdf fine(context());
      uint64_t traced = 0;
      uint32_t second = 0;
      for (int update = 0; update < 4; ++update) {
        fine.update(gpu_scene, coarse, grid, settings);
        traced += fine.read_traced_texels();
        if (update == 1) second = fine.read_traced_texels();
      }
      return Outcome{reference::compare_fine(fine.read_distance(), exact, grid, 2.0f).mean_abs_voxels, traced,
                     second, fine.read_traced_texels()};
    };
    const Outcome full = run(false), still = run(true);
    std::printf("%s, 4 updates: retracing all %.4f fine voxels from %lu texels traced; skipping converged %.4f "
                "from %lu (%u in the second update, %u in the last)\n",
                path.c_str(), full.mean_abs_voxels, (unsigned long)full.traced, still.mean_abs_voxels,
                (unsigned long)still.traced, still.second_traced, still.last_traced);
    EXPECT_LE(double(still.traced), 0.5 * double(full.traced));
    EXPECT_LT(still.second_traced, full.second_traced / 2)
        << "the second update traces only the texels that may improve (fine_probe.comp)";
    EXPECT_LT(still.last_traced, full.last_traced / 20) << "the last update retraces only what still improves";
    EXPECT_LT(still.mean_abs_voxels, full.mean_abs_voxels + 0.05);
  }
}

TEST_F(FineSdfTest, InsideOfClosedMeshIsNegative) {
  GpuScene scene(context(), single_mesh_scene(reference::uv_sphere({0, 0, 0}, 1.0f, 64)));
  Built b = build(scene, 32, 64, 8);
  size_t inside = 0, negative = 0;
  for (int z = 0; z < b.grid.dims.z; ++z)
    for (int y = 0; y < b.grid.dims.y; ++y)
      for (int x = 0; x < b.grid.dims.x; ++x) {
        float r = glm::length(b.grid.voxel_center({x, y, z}));
        float value = b.fine[size_t(x) + size_t(b.grid.dims.x) * (y + size_t(b.grid.dims.y) * z)];
        // Just inside the surface, within the traced band.
        if (r < 1.0f - b.grid.voxel_size && r > 1.0f - 3.0f * b.grid.voxel_size) inside++, negative += value < 0;
      }
  ASSERT_GT(inside, 100u);
  EXPECT_EQ(negative, inside);
}

}  // namespace
}  // namespace rtsdf

namespace rtsdf {
namespace {

// A sphere moves by less than the trace band, so its old surface stays in the
// band. There the texel forgets the old surface only through the decay:
// the gap to the new (larger) distance shrinks as alpha^t, from at most
// g0 = (d + beta + sqrt(3)/2) coarse voxels (the decay target's upper bound).
// It must be below one fine voxel within t = ceil(ln(1 / g0) / ln(alpha)) frames.
TEST_F(FineSdfTest, MovedSphereOldPlaceRecoversWithinDecayBound) {
  const float radius = 0.35f;
  Mesh mesh = reference::uv_sphere({0, 0, 0}, radius, 48);
  // Two tiny markers pin the scene bounds, so the grid stays put while the sphere moves.
  Mesh markers = reference::box({-1, -1, -1}, {-0.98f, -0.98f, -0.98f});
  reference::append(markers, reference::box({0.98f, 0.98f, 0.98f}, {1, 1, 1}));
  Scene scene;
  scene.meshes = {mesh, markers};
  const glm::vec3 before(-0.2f, 0, 0), after(-0.1f, 0, 0);
  scene.instances = {{0, glm::translate(glm::mat4(1.0f), before)}, {1, glm::mat4(1.0f)}};
  GpuScene gpu_scene(context(), scene);

  FineTraceSettings settings;  // alpha 0.9, d 2 coarse voxels
  CoarseSdf coarse(context());
  FineSdf fine(context());
  const GridSpec coarse_grid = fit_grid(gpu_scene.bounds(), 32);
  const GridSpec grid = FineSdf::fit(coarse_grid, 64);
  const float ratio = coarse_grid.voxel_size / grid.voxel_size;
  ASSERT_LT(glm::length(after - before), settings.trace_band * coarse_grid.voxel_size);
  for (int f = 0; f < 12; ++f) {
    coarse.build(gpu_scene, coarse_grid, 0.5f);
    fine.update(gpu_scene, coarse, grid, settings);
  }

  gpu_scene.set_transforms({glm::translate(glm::mat4(1.0f), after), glm::mat4(1.0f)});
  const double g0 = (settings.trace_band + 0.5 + 0.5 * std::sqrt(3.0)) * ratio;  // fine voxels
  const int bound = int(std::ceil(std::log(1.0 / g0) / std::log(double(settings.decay))));
  int recovered_at = -1;
  for (int frame = 1; frame <= bound + 4 && recovered_at < 0; ++frame) {
    coarse.build(gpu_scene, coarse_grid, 0.5f);
    fine.update(gpu_scene, coarse, grid, settings);
    std::vector<float> values = fine.read_distance();
    double worst = 0;
    for (int z = 0; z < grid.dims.z; ++z)
      for (int y = 0; y < grid.dims.y; ++y)
        for (int x = 0; x < grid.dims.x; ++x) {
          glm::vec3 p = grid.voxel_center({x, y, z});
          float old_distance = glm::length(p - before) - radius;
          float now = glm::length(p - after) - radius;
          // Texels on the old surface that are now well outside the sphere.
          if (std::abs(old_distance) > 0.5f * grid.voxel_size || now < 2.0f * grid.voxel_size) continue;
          float value = values[size_t(x) + size_t(grid.dims.x) * (y + size_t(grid.dims.y) * z)];
          worst = std::max(worst, double(now - value) / grid.voxel_size);  // how far below the truth
        }
    std::printf("moved sphere, frame %d: worst stale underestimate %.2f fine voxels (bound %d frames)\n", frame,
                worst, bound);
    if (worst <= 1.0) recovered_at = frame;
  }
  EXPECT_GT(recovered_at, 0) << "the old place did not recover";
  EXPECT_LE(recovered_at, bound);
}

// The sign must follow a moved object at once: texels the sphere has left
// (inside it before, well outside it now) read positive after one update.
// Hit counts decaying with the distance kept the old inside for tens of
// frames: a dark ghost of the old shadow in the viewport.
TEST_F(FineSdfTest, MovedSphereLeavesNoInsideBehind) {
  const float radius = 0.35f;
  Scene scene;
  scene.meshes = {reference::uv_sphere({0, 0, 0}, radius, 48), reference::box({-1, -1, -1}, {-0.98f, -0.98f, -0.98f})};
  reference::append(scene.meshes[1], reference::box({0.98f, 0.98f, 0.98f}, {1, 1, 1}));  // pin the grid
  const glm::vec3 before(-0.25f, 0, 0), after(0.25f, 0, 0);
  scene.instances = {{0, glm::translate(glm::mat4(1.0f), before)}, {1, glm::mat4(1.0f)}};
  GpuScene gpu_scene(context(), scene);
  CoarseSdf coarse(context());
  FineSdf fine(context());
  const GridSpec coarse_grid = fit_grid(gpu_scene.bounds(), 32);
  const GridSpec grid = FineSdf::fit(coarse_grid, 64);
  auto frame = [&] {
    coarse.build(gpu_scene, coarse_grid, 0.5f);
    fine.update(gpu_scene, coarse, grid, FineTraceSettings{});
  };
  for (int f = 0; f < 16; ++f) frame();
  gpu_scene.set_transforms({glm::translate(glm::mat4(1.0f), after), glm::mat4(1.0f)});
  frame();
  std::vector<float> values = fine.read_distance();
  size_t left = 0, still_inside = 0;
  for (int z = 0; z < grid.dims.z; ++z)
    for (int y = 0; y < grid.dims.y; ++y)
      for (int x = 0; x < grid.dims.x; ++x) {
        glm::vec3 p = grid.voxel_center({x, y, z});
        if (glm::length(p - before) - radius > -grid.voxel_size || glm::length(p - after) - radius < grid.voxel_size)
          continue;
        left++;
        still_inside += values[size_t(x) + size_t(grid.dims.x) * (y + size_t(grid.dims.y) * z)] < 0.0f;
      }
  std::printf("moved sphere: %zu of %zu texels it left still read inside after one frame\n", still_inside, left);
  ASSERT_GT(left, 500u);
  EXPECT_EQ(still_inside, 0u);
}

// After one of two far-apart spheres moves, the next update traces only the
// band near the moved one's old and new places: the other's texels keep their
// values exactly, and the moved one's field is as good as a full update's.
TEST_F(FineSdfTest, LocalChangeRetracesOnlyNearIt) {
  const float radius = 0.3f;
  Scene scene;
  scene.meshes = {reference::uv_sphere({0, 0, 0}, radius, 32)};
  const glm::vec3 still(1.2f, 0, 0), before(-1.2f, 0, 0), after(-1.0f, 0, 0);
  scene.instances = {{0, glm::translate(glm::mat4(1.0f), still)}, {0, glm::translate(glm::mat4(1.0f), before)}};
  GpuScene gpu_scene(context(), scene);
  CoarseSdf coarse(context());
  FineSdf local(context()), full(context());
  const GridSpec coarse_grid = fit_grid(Bounds{glm::vec3(-1.6f), glm::vec3(1.6f)}, 32);
  const GridSpec grid = FineSdf::fit(coarse_grid, 64);
  coarse.build(gpu_scene, coarse_grid, 0.5f);
  for (int f = 0; f < 8; ++f) local.update(gpu_scene, coarse, grid, FineTraceSettings{}), full.update(gpu_scene, coarse, grid, FineTraceSettings{});
  const uint32_t band = full.read_traced_texels();
  const std::vector<float> converged = local.read_distance();
  gpu_scene.take_changes();

  gpu_scene.set_transforms({glm::translate(glm::mat4(1.0f), still), glm::translate(glm::mat4(1.0f), after)});
  const GpuScene::Changes changes = gpu_scene.take_changes();
  ASSERT_TRUE(changes.any && !changes.everything);
  EXPECT_LT(changes.region.hi.x, 0.0f) << "the region holds only the moved sphere";
  coarse.build(gpu_scene, coarse_grid, 0.5f);
  local.update(gpu_scene, coarse, grid, FineTraceSettings{}, &changes.region);
  full.update(gpu_scene, coarse, grid, FineTraceSettings{});
  const uint32_t traced = local.read_traced_texels();
  std::printf("local change: %u texels traced of a band of %u\n", traced, band);
  EXPECT_LT(traced, band * 3 / 4);
  EXPECT_GT(traced, band / 4);

  const std::vector<float> local_values = local.read_distance(), full_values = full.read_distance();
  size_t kept = 0, near_still = 0, wrong_sign = 0, near_moved = 0;
  for (int z = 0; z < grid.dims.z; ++z)
    for (int y = 0; y < grid.dims.y; ++y)
      for (int x = 0; x < grid.dims.x; ++x) {
        const size_t i = size_t(x) + size_t(grid.dims.x) * (y + size_t(grid.dims.y) * z);
        const glm::vec3 p = grid.voxel_center({x, y, z});
        if (glm::length(p - still) < radius + 2.0f * grid.voxel_size && p.x > 0.6f)
          near_still++, kept += local_values[i] == converged[i];
        const float now = glm::length(p - after) - radius;
        if (std::abs(now) > 1.5f * grid.voxel_size && std::abs(now) < 3.0f * grid.voxel_size)
          near_moved++, wrong_sign += (local_values[i] < 0.0f) != (now < 0.0f);
      }
  ASSERT_GT(near_still, 100u);
  EXPECT_EQ(kept, near_still) << "texels far from the change must keep their values";
  ASSERT_GT(near_moved, 100u);
  EXPECT_EQ(wrong_sign, 0u);
}

}  // namespace
}  // namespace rtsdf

namespace rtsdf {
namespace {

// Fine-SDF statistics over the texels `select` picks: mean |fine - exact| in
// fine voxels and the share whose sign differs from `expect_negative`.
struct Band {
  double mean_error = 0;
  double wrong_sign = 0;
  size_t count = 0;
};
template <typename Exact, typename Select, typename ExpectNegative>
Band measure(const GridSpec& grid, const std::vector<float>& fine, Exact exact, Select select,
             ExpectNegative expect_negative) {
  Band band;
  double sum = 0;
  size_t wrong = 0;
  for (int z = 0; z < grid.dims.z; ++z)
    for (int y = 0; y < grid.dims.y; ++y)
      for (int x = 0; x < grid.dims.x; ++x) {
        glm::vec3 p = grid.voxel_center({x, y, z});
        if (!select(p)) continue;
        float value = fine[size_t(x) + size_t(grid.dims.x) * (y + size_t(grid.dims.y) * z)];
        sum += std::abs(std::abs(value) - exact(p)) / grid.voxel_size;
        wrong += (value < 0.0f) != expect_negative(p);
        band.count++;
      }
  band.mean_error = band.count ? sum / double(band.count) : 0.0;
  band.wrong_sign = band.count ? double(wrong) / double(band.count) : 0.0;
  return band;
}

// Distance |z| - reach (a slab reaching `reach` voxels either side of the
// plane z = 0) over the central texels within three voxels of the plane.
void expect_slab(const GridSpec& grid, const std::vector<float>& fine, float reach_voxels, const char* label) {
  const float v = grid.voxel_size, reach = reach_voxels * v;
  Band band = measure(
      grid, fine, [&](glm::vec3 p) { return std::abs(std::abs(p.z) - reach); },
      [&](glm::vec3 p) {
        // (leaving out the slab's faces, where the sign is a coin toss)
        return std::abs(p.x) < 0.6f && std::abs(p.y) < 0.6f && std::abs(p.z) < 3.0f * v &&
               std::abs(std::abs(p.z) - reach) > 0.25f * v;
      },
      [&](glm::vec3 p) { return std::abs(p.z) < reach; });
  std::printf("%s 32/64: mean |fine - (|z| - %.2f voxel)| %.3f fine voxels, wrong sign %.2f%% of %zu\n", label,
              reach_voxels, band.mean_error, 100.0 * band.wrong_sign, band.count);
  ASSERT_GT(band.count, 500u);
  EXPECT_LT(band.mean_error, 0.35);
  EXPECT_LT(band.wrong_sign, 0.02);
}

// A one-sided sheet has no inside. Counting back faces would mark the whole
// band behind it as inside (and shadows would spread from there); instead it
// reads as a slab one fine voxel thick on either side.
TEST_F(FineSdfTest, OneSidedSheetIsAThinSlabOnBothSides) {
  Mesh sheet = reference::sheet({-0.8f, -0.8f}, {0.8f, 0.8f}, 0.0f);  // normal +z
  reference::append(sheet, reference::box({-1, -1, -0.5f}, {-0.98f, -0.98f, -0.48f}));  // pins the bounds
  reference::append(sheet, reference::box({0.98f, 0.98f, 0.48f}, {1, 1, 0.5f}));
  GpuScene scene(context(), single_mesh_scene(sheet));
  Built b = build(scene, 32, 64, 16);
  expect_slab(b.grid, b.fine, 1.0f, "one-sided sheet");
}

// A flat mesh alone: its grid is centred on it, and with an odd number of
// texels across (coarse 64, fine 96: 9) the middle layer's centres lie on the
// sheet itself. Rays from there start on the triangles and met them from no
// direction: that layer read clear (+1.3 voxels), the sheet had no slab, and
// the sun came through an Archimesh room's ceiling.
TEST_F(FineSdfTest, SheetThroughTexelCentresIsStillASlab) {
  GpuScene scene(context(), single_mesh_scene(reference::sheet({0.0f, 0.0f}, {5.0f, 4.0f}, 2.6f)));
  Built b = build(scene, 64, 96, 2);
  ASSERT_EQ(b.grid.dims.z % 2, 1);
  const int middle = b.grid.dims.z / 2;
  ASSERT_NEAR(b.grid.voxel_center({0, 0, middle}).z, 2.6f, 1e-3f * b.grid.voxel_size) << "a layer on the sheet";
  size_t count = 0, clear = 0;
  for (int y = 0; y < b.grid.dims.y; ++y)
    for (int x = 0; x < b.grid.dims.x; ++x) {
      const glm::vec3 p = b.grid.voxel_center({x, y, middle});
      if (p.x < 0.5f || p.x > 4.5f || p.y < 0.5f || p.y > 3.5f) continue;
      count++;
      clear += b.fine[size_t(x) + size_t(b.grid.dims.x) * (y + size_t(b.grid.dims.y) * middle)] > -0.9f * b.grid.voxel_size;
    }
  std::printf("sheet through texel centres: %zu of %zu texels on it read less than 0.9 voxel inside\n", clear, count);
  ASSERT_GT(count, 1000u);
  EXPECT_EQ(clear, 0u);
}

// A closed plate far thinner than a voxel has no texel inside it: marches
// through it would never read a negative value. It reads as a slab too, half
// a voxel beyond its faces, with no gap across it.
TEST_F(FineSdfTest, ClosedPlateThinnerThanAVoxelIsAThinSlab) {
  const float half = 0.001f;
  Mesh plate = reference::box({-0.8f, -0.8f, -half}, {0.8f, 0.8f, half});
  reference::append(plate, reference::box({-1, -1, -0.5f}, {-0.98f, -0.98f, -0.48f}));
  reference::append(plate, reference::box({0.98f, 0.98f, 0.48f}, {1, 1, 0.5f}));
  GpuScene scene(context(), single_mesh_scene(plate));
  Built b = build(scene, 32, 64, 16);
  expect_slab(b.grid, b.fine, half / b.grid.voxel_size + 0.5f, "closed plate 0.002 thick");
}

// A deforming mesh (same triangles, new positions): the sphere grows from 0.45
// to 0.55; after the decay bound the fine SDF matches the new sphere and its
// old surface, now inside, reads negative.
// Near surfaces only (as the renderer's fields are), a brick far from every
// surface in one update is left as it was. Where a surface moves into it
// (a deforming mesh in its kept grid), its texels start afresh in that
// update, every one traced whatever its turn: one update puts the band
// there as near the truth as a new field's first update (its 8 rays may
// miss the nearest point by a voxel or so), with the right signs. A
// whole-grid classify, keeping the far values it wrote there, had 546 of
// these 708 texels off.
TEST_F(FineSdfTest, ABrickASurfaceMovesIntoStartsAfresh) {
  const float radius = 0.2f;
  Scene scene;
  scene.meshes = {reference::uv_sphere({0, 0, 0}, radius, 48), reference::box({-1, -1, -1}, {-0.98f, -0.98f, -0.98f})};
  reference::append(scene.meshes[1], reference::box({0.98f, 0.98f, 0.98f}, {1, 1, 1}));  // pin the grid
  const glm::vec3 before(-0.55f, 0, 0), after(0.5f, 0.1f, 0);
  scene.instances = {{0, glm::translate(glm::mat4(1.0f), before)}, {1, glm::mat4(1.0f)}};
  GpuScene gpu_scene(context(), scene);
  CoarseSdf coarse(context());
  FineSdf fine(context());
  FineTraceSettings settings;
  settings.near_surface_only = true;
  settings.interleave = 4;  // (on a later update, a quarter of the band's texels take their turn)
  const GridSpec coarse_grid = fit_grid(gpu_scene.bounds(), 32);
  const GridSpec grid = FineSdf::fit(coarse_grid, 64);
  auto frame = [&] {
    coarse.build(gpu_scene, coarse_grid, 0.5f);
    fine.update(gpu_scene, coarse, grid, settings);
  };
  for (int f = 0; f < 6; ++f) frame();
  gpu_scene.set_transforms({glm::translate(glm::mat4(1.0f), after), glm::mat4(1.0f)});
  frame();
  const std::vector<float> values = fine.read_distance();
  const float v = grid.voxel_size;
  size_t near = 0, wrong = 0;
  for (int z = 0; z < grid.dims.z; ++z)
    for (int y = 0; y < grid.dims.y; ++y)
      for (int x = 0; x < grid.dims.x; ++x) {
        const glm::vec3 p = grid.voxel_center({x, y, z});
        const float truth = glm::length(p - after) - radius;
        if (std::abs(truth) > 1.5f * v || std::abs(truth) < 0.5f * v) continue;
        near++;
        const float value = values[size_t(x) + size_t(grid.dims.x) * (y + size_t(grid.dims.y) * z)];
        wrong += !(value >= truth - v && value <= truth + 2.0f * v && (value < 0.0f) == (truth < 0.0f));
      }
  std::printf("sphere moved into far bricks: %zu of %zu texels near its new surface off or of the wrong sign\n",
              wrong, near);
  ASSERT_GT(near, 500u);
  EXPECT_EQ(wrong, 0u);
}

TEST_F(FineSdfTest, DeformingMeshFollowsNewPositions) {
  Mesh sphere = reference::uv_sphere({0, 0, 0}, 0.45f, 48);
  Mesh markers = reference::box({-1, -1, -1}, {-0.98f, -0.98f, -0.98f});
  reference::append(markers, reference::box({0.98f, 0.98f, 0.98f}, {1, 1, 1}));
  Scene scene;
  scene.meshes = {sphere, markers};
  scene.instances = {{0, glm::mat4(1.0f)}, {1, glm::mat4(1.0f)}};
  GpuScene gpu_scene(context(), scene);
  CoarseSdf coarse(context());
  FineSdf fine(context());
  FineTraceSettings settings;
  const GridSpec coarse_grid = fit_grid(gpu_scene.bounds(), 32);
  const GridSpec grid = FineSdf::fit(coarse_grid, 64);
  auto frames = [&](int n) {
    for (int f = 0; f < n; ++f) {
      coarse.build(gpu_scene, coarse_grid, 0.5f);
      fine.update(gpu_scene, coarse, grid, settings);
    }
  };
  frames(8);
  std::vector<glm::vec3> grown;
  for (const glm::vec3& p : sphere.positions) grown.push_back(p * (0.55f / 0.45f));
  gpu_scene.set_mesh_positions(0, grown);
  frames(24);  // above ceil(ln(1/g0)/ln(alpha)) = 19 frames for alpha 0.9 (see MovedSphere...)
  const float v = grid.voxel_size;
  Band band = measure(
      grid, fine.read_distance(), [](glm::vec3 p) { return std::abs(glm::length(p) - 0.55f); },
      [&](glm::vec3 p) { return std::abs(glm::length(p) - 0.55f) < 2.0f * v && std::abs(glm::length(p) - 0.55f) > 0.5f * v; },
      [](glm::vec3 p) { return glm::length(p) < 0.55f; });
  std::printf("deformed sphere 32/64: mean %.3f fine voxels, wrong sign %.2f%% of %zu\n", band.mean_error,
              100.0 * band.wrong_sign, band.count);
  ASSERT_GT(band.count, 500u);
  EXPECT_LT(band.mean_error, 0.35);
  EXPECT_LT(band.wrong_sign, 0.02);
}

// A real mesh (long thin triangles, open boundaries) under a travelling
// wave, as a deforming mesh's field is updated in a viewport: every frame a
// new shape, a new coarse SDF and one trace of each band texel with its
// history kept, with the few rays such a field traces (each texel measures
// its kept nearest triangle again in the new shape, fine_trace.comp). After
// 12 frames of motion, up to about two fine voxels a frame, against
// OpenVDB's exact field. When texels kept only a decaying value, 8 rays a
// frame gave a mean error of 0.320 fine voxels here (what a surface left
// behind stays until the decay forgets it).
// Traced in turns (interleave > 1, as the viewport traces), the texels off
// their turn measure their kept triangles again without rays: left as they
// were, they held the distances of up to interleave - 1 frames ago, and
// at the viewport's 4 the mean error was 1.066 fine voxels with 18% of
// the signs wrong.
// With `surface_moves`, each update is told how far the surface moved since
// the last (GpuScene::mesh_move_since), as a mesh's own field is. The wave
// advances `step` radians a frame (0.5: up to about two fine voxels).
struct WaveResult {
  reference::FineErrors errors;
  uint64_t doubted = 0;  // texels whose sign the 12 updates of motion doubted
};

WaveResult follow_a_wave(const vk::Context& context, int interleave, bool surface_moves, float step = 0.5f) {
  const std::string path = testing::test_mesh_path();
  Scene scene = import_scene(path);
  EXPECT_EQ(scene.meshes.size(), 1u);
  const std::vector<glm::vec3> rest = scene.meshes[0].positions;
  GpuScene gpu_scene(context, scene);
  Bounds bounds = gpu_scene.bounds();
  const glm::vec3 extent = bounds.extent();
  const float length = std::max(extent.x, std::max(extent.y, extent.z)), amplitude = 0.05f * length;
  bounds.lo -= glm::vec3(2.0f * amplitude);
  bounds.hi += glm::vec3(2.0f * amplitude);
  const GridSpec coarse_grid = fit_grid(bounds, 64);
  const GridSpec grid = FineSdf::fit(coarse_grid, 96);
  // The wave runs along x and lifts along z.
  auto wave = [&](int frame) {
    std::vector<glm::vec3> moved = rest;
    for (glm::vec3& p : moved) p.z += amplitude * std::sin(6.2831853f * (p.x - bounds.lo.x) / length - step * float(frame));
    return moved;
  };
  CoarseSdf coarse(context);
  FineSdf fine(context);
  FineTraceSettings settings;
  uint64_t version = 0;
  double travel = 0.0;
  WaveResult result;
  auto update = [&](int frame) {
    gpu_scene.set_mesh_positions(0, wave(frame));
    coarse.build(gpu_scene, coarse_grid, 0.5f);
    double moved;
    travel = gpu_scene.mesh_move_since(0, version, travel, moved);
    version = gpu_scene.mesh_version(0);
    const float move = surface_moves ? float(moved) : gpu::kUnknownSurfaceMove;
    fine.update(gpu_scene.ray_structures().targets(), coarse, grid, settings, nullptr, move);
    if (frame > 0) result.doubted += fine.read_doubted_texels();
  };
  for (int frame = 0; frame < 8; ++frame) update(0);  // (converged on the first shape)
  settings.rays_per_texel = kDeformingRaysPerTexel;
  settings.interleave = interleave;
  for (int frame = 1; frame <= 12; ++frame) update(frame);
  Scene last = scene;
  last.meshes[0].positions = wave(12);
  const std::vector<float> exact = reference::signed_distance(last, grid, 3.0f);
  result.errors = reference::compare_fine(fine.read_distance(), exact, grid, 2.0f);
  std::printf("%s under a wave of %g radians a frame, 12 frames of %d rays, interleave %d, %s: mean |fine-exact| "
              "%.3f fine voxels over %zu, wrong signs %.2f%%, %llu texels doubted\n",
              path.c_str(), step, settings.rays_per_texel, interleave,
              surface_moves ? "the surface's moves told" : "no moves told",
              result.errors.mean_abs_voxels, result.errors.band_voxels, 100.0 * result.errors.wrong_sign_share,
              static_cast<unsigned long long>(result.doubted));
  EXPECT_GT(result.errors.band_voxels, 1000u);
  EXPECT_LE(result.errors.mean_abs_voxels, 0.2);
  EXPECT_LE(result.errors.wrong_sign_share, 0.01);
  return result;
}

TEST_F(FineSdfTest, ADeformingRealMeshIsFollowedWithFewRays) { follow_a_wave(context(), 1, true); }

TEST_F(FineSdfTest, ADeformingRealMeshIsFollowedWhenTracedInTurns) { follow_a_wave(context(), 4, true); }

// Off its turn, a texel doubts its sign where the side of its nearest
// triangle's plane contradicts it (the surface may have crossed it), and
// takes the winding number. Where the surface lies farther from it than the
// surface moved since the last update, it cannot have crossed: told the
// move, the field takes fewer winding numbers, and its signs are as right.
// A slow wave (a fifth of a voxel a frame at most), as a character's
// surface moves between viewport frames (a fine voxel a frame at most).
TEST_F(FineSdfTest, TexelsBeyondTheSurfacesMoveKeepTheirSignWithoutDoubt) {
  const WaveResult told = follow_a_wave(context(), 4, true, 0.05f), untold = follow_a_wave(context(), 4, false, 0.05f);
  EXPECT_LT(double(told.doubted), 0.9 * double(untold.doubted));
  EXPECT_LE(told.errors.wrong_sign_share, untold.errors.wrong_sign_share + 0.001);
  EXPECT_LE(told.errors.mean_abs_voxels, untold.errors.mean_abs_voxels + 0.01);
}

}  // namespace
}  // namespace rtsdf
