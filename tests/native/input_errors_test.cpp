// Bad input ends in a clear rtsdf::Error, never a crash.
#include <cmath>
#include <limits>

#include "coarse_sdf.h"
#include "mesh_import.h"
#include "reference/shapes.h"
#include "renderer.h"
#include <glm/gtc/matrix_transform.hpp>
#include "vulkan_test.h"

namespace rtsdf {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

class InputErrors : public testing::VulkanTest {};

TEST_F(InputErrors, EmptySceneAndMeshWithoutTriangles) {
  EXPECT_NE(error_of([] { Scene().validate(); }).find("no triangles"), std::string::npos);
  Mesh points;
  points.name = "points";
  points.positions = {{0, 0, 0}, {1, 1, 1}};
  EXPECT_NE(error_of([&] { single_mesh_scene(points).validate(); }).find("no triangles"), std::string::npos);
}

TEST_F(InputErrors, NonFiniteAndHugeCoordinates) {
  Mesh mesh = reference::single_triangle({0, 0, 0}, {1, 0, 0}, {0, std::nanf(""), 0});
  EXPECT_NE(error_of([&] { single_mesh_scene(mesh).validate(); }).find("NaN"), std::string::npos);
  mesh.positions[2].y = std::numeric_limits<float>::infinity();
  EXPECT_NE(error_of([&] { single_mesh_scene(mesh).validate(); }).find("infinite"), std::string::npos);
  mesh.positions = {{-3e38f, 0, 0}, {3e38f, 0, 0}, {0, 1, 0}};
  EXPECT_NE(error_of([&] { single_mesh_scene(mesh).validate(); }).find("too large"), std::string::npos);
  Scene scene = single_mesh_scene(reference::single_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  scene.instances[0].object_to_world[3][0] = std::nanf("");
  EXPECT_NE(error_of([&] { scene.validate(); }).find("transform"), std::string::npos);
}

TEST_F(InputErrors, DegenerateSceneAndBadIndices) {
  Mesh point = reference::single_triangle({1, 1, 1}, {1, 1, 1}, {1, 1, 1});
  EXPECT_NE(error_of([&] { single_mesh_scene(point).validate(); }).find("zero extent"), std::string::npos);
  Mesh bad = reference::single_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  bad.indices[2] = 7;
  EXPECT_NE(error_of([&] { single_mesh_scene(bad).validate(); }).find("index"), std::string::npos);
}

TEST_F(InputErrors, ResolutionOutOfRange) {
  Bounds bounds{{0, 0, 0}, {1, 1, 1}};
  for (int resolution : {-1, 0, 3, 1025, 100000})
    EXPECT_NE(error_of([&] { fit_grid(bounds, resolution); }).find("out of range"), std::string::npos) << resolution;
  EXPECT_EQ(fit_grid(bounds, 4).dims, glm::ivec3(4));
  EXPECT_EQ(fit_grid(bounds, 1024).dims, glm::ivec3(1024));
}

TEST_F(InputErrors, GridTooBigForDeviceMemory) {
  // A grid larger than any device heap is refused before allocating.
  GpuScene scene(context(), single_mesh_scene(reference::single_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0})));
  GridSpec grid;
  grid.dims = glm::ivec3(1024);
  grid.voxel_size = 1.0f / 1024.0f;
  const size_t needed = coarse_sdf_bytes(grid);
  if (needed <= context().device_local_heap_bytes() * 3 / 4) GTEST_SKIP() << "device is large enough for 1024^3";
  CoarseSdf coarse(context());
  EXPECT_NE(error_of([&] { coarse.build(scene, grid, 0.5f); }).find("lower the resolution"), std::string::npos);
}

TEST_F(InputErrors, MissingAndUnreadableFiles) {
  EXPECT_NE(error_of([] { import_scene("/nonexistent/mesh.obj"); }).find("cannot open"), std::string::npos);
  const char* path = "/tmp/rtsdf_test_garbage.ply";
  FILE* f = std::fopen(path, "w");
  std::fputs("ply\nthis is not a mesh\n", f);
  std::fclose(f);
  EXPECT_NE(error_of([&] { import_scene(path); }).find("cannot read"), std::string::npos);
}

TEST_F(InputErrors, DynamicUpdatesRejectBadTransformsAndVertexCounts) {
  GpuScene scene(context(), single_mesh_scene(reference::single_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0})));
  glm::mat4 bad(1.0f);
  bad[3][1] = std::nanf("");
  EXPECT_NE(error_of([&] { scene.set_transforms({bad}); }).find("NaN"), std::string::npos);
  EXPECT_NE(error_of([&] { scene.set_transforms({}); }).find("expected 1"), std::string::npos);
  EXPECT_NE(error_of([&] { scene.set_mesh_positions(0, {{0, 0, 0}}); }).find("vertex count"), std::string::npos);
  Mesh bad_mesh = reference::single_triangle({0, 0, 0}, {1, 0, 0}, {0, std::nanf(""), 0});
  EXPECT_NE(error_of([&] { scene.set_mesh(0, bad_mesh); }).find("NaN"), std::string::npos);
  bad_mesh.positions = {{-3e38f, 0, 0}, {3e38f, 0, 0}, {0, 1, 0}};
  EXPECT_NE(error_of([&] { scene.set_mesh(0, bad_mesh); }).find("too large"), std::string::npos);
  bad_mesh.indices.clear();
  EXPECT_NE(error_of([&] { scene.set_mesh(0, bad_mesh); }).find("no triangles"), std::string::npos);
  EXPECT_NE(error_of([&] { scene.set_mesh(1, bad_mesh); }).find("no mesh 1"), std::string::npos);
  // The scene is unchanged by the refused updates.
  EXPECT_EQ(scene.instances()[0].object_to_world, glm::mat4(1.0f));
  EXPECT_EQ(scene.scene().meshes[0].positions[1], glm::vec3(1, 0, 0));
  EXPECT_EQ(scene.mesh_version(0), 0u);
  EXPECT_EQ(scene.bounds().hi.x, 1.0f);
}

TEST_F(InputErrors, DegenerateCameraIsRefused) {
  GpuScene scene(context(), single_mesh_scene(reference::box({0, 0, 0}, {1, 1, 1})));
  Renderer renderer(context());
  Camera camera;
  camera.world_to_view = glm::lookAt(glm::vec3(3, 3, 3), glm::vec3(0), glm::vec3(0, 0, 1));
  camera.projection = glm::mat4(0.0f);  // (no projection at all)
  auto begin = [&] { renderer.begin(scene, camera, {}, glm::vec3(0.1f), 16, 16, RenderSettings{}, true); };
  EXPECT_NE(error_of(begin).find("camera"), std::string::npos);
  camera.projection = glm::perspective(0.8f, 1.0f, 0.1f, 10.0f);
  camera.world_to_view[3][0] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(error_of(begin).find("camera"), std::string::npos);
  camera.world_to_view[3][0] = 0.0f;
  EXPECT_EQ(error_of(begin), "") << "a proper camera renders";
}

TEST_F(InputErrors, NoMatchingDeviceName) {
  vk::ContextOptions options;
  options.device_name = "no-such-device-xyz";
  EXPECT_NE(error_of([&] { vk::Context c(options); }).find("matches no Vulkan device"), std::string::npos);
}

}  // namespace
}  // namespace rtsdf
