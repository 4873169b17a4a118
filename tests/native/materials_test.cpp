// Materials in the G-buffer: each triangle's material slot picks its
// instance's colour, an image is sampled by the mesh's UVs (repeating,
// sRGB-decoded), vertex colours multiply the base colour of slots that take
// them, and bad material input is refused with a clear error.
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "error.h"
#include "reference/shapes.h"
#include "renderer.h"
#include "vulkan_test.h"

namespace rtsdf {
namespace {

class MaterialsTest : public testing::VulkanTest {};

constexpr int kSize = 32;

// The sheet [-1, 1]^2 seen from straight above under a sun straight down: the image is the base colour times the light.
RenderOutput render_from_above(const Scene& scene) {
  Camera camera;
  camera.world_to_view = glm::lookAt(glm::vec3(0, 0, 5), glm::vec3(0), glm::vec3(0, 1, 0));
  camera.projection = glm::orthoRH_NO(-1.0f, 1.0f, -1.0f, 1.0f, 0.1f, 10.0f);
  camera.orthographic = true;
  Light sun;
  sun.type = LightType::Sun;
  sun.direction = glm::vec3(0, 0, -1);
  sun.energy = 3.0f;
  GpuScene gpu_scene(testing::VulkanTest::context(), scene);
  RenderSettings settings;
  settings.samples = 1;
  settings.shadow_method = ShadowMethod::RayTraced;  // (no field: the colours are the point)
  Renderer renderer(testing::VulkanTest::context());
  return renderer.render(gpu_scene, camera, {sun}, glm::vec3(0.0f), kSize, kSize, settings);
}

// The colour at world (x, y) on the sheet, normalized to its brightest channel.
glm::vec3 hue_at(const RenderOutput& out, float x, float y) {
  const int column = int((x + 1.0f) * 0.5f * kSize), row = int((1.0f - y) * 0.5f * kSize);  // (rows top to bottom)
  const float* p = &out.combined[4 * (size_t(row) * kSize + column)];
  const glm::vec3 rgb(p[0], p[1], p[2]);
  return rgb / std::max(std::max(rgb.r, rgb.g), std::max(rgb.b, 1e-6f));
}

Scene sheet_scene() {
  Scene scene;
  scene.meshes = {reference::sheet({-1, -1}, {1, 1}, 0.0f)};
  scene.instances = {{0, glm::mat4(1.0f)}};
  return scene;
}

// (0.1: a pixel's jittered sample reaches a little into the next texel)
void expect_hue(glm::vec3 hue, glm::vec3 expected, const char* where) {
  EXPECT_NEAR(hue.r, expected.r, 0.1f) << where;
  EXPECT_NEAR(hue.g, expected.g, 0.1f) << where;
  EXPECT_NEAR(hue.b, expected.b, 0.1f) << where;
}

TEST_F(MaterialsTest, EachTriangleShowsItsSlotsColour) {
  Scene scene = sheet_scene();
  scene.meshes[0].materials = {0, 1};  // (triangle 0: below the diagonal from (-1, -1) to (1, 1))
  scene.instances[0].materials = {{glm::vec3(0.8f, 0.0f, 0.0f)}, {glm::vec3(0.0f, 0.0f, 0.8f)}};
  const RenderOutput out = render_from_above(scene);
  expect_hue(hue_at(out, 0.5f, -0.5f), {1, 0, 0}, "slot 0");
  expect_hue(hue_at(out, -0.5f, 0.5f), {0, 0, 1}, "slot 1");

  // A slot past the instance's last takes the last; no slots at all: the base colour.
  scene.meshes[0].materials = {0, 7};
  expect_hue(hue_at(render_from_above(scene), -0.5f, 0.5f), {0, 0, 1}, "slot 7 of 2");
  scene.instances[0].materials.clear();
  scene.instances[0].base_color = glm::vec3(0.0f, 0.6f, 0.0f);
  expect_hue(hue_at(render_from_above(scene), -0.5f, 0.5f), {0, 1, 0}, "no slots");
}

uint32_t rgba8(int r, int g, int b) { return uint32_t(r) | uint32_t(g) << 8 | uint32_t(b) << 16 | 255u << 24; }

TEST_F(MaterialsTest, AnImageIsSampledByTheUvs) {
  Scene scene = sheet_scene();
  // A 2 x 2 image, rows from the bottom: red, green / blue, sRGB 50% grey.
  scene.textures = {{"quad", 2, 2, {rgba8(255, 0, 0), rgba8(0, 255, 0), rgba8(0, 0, 255), rgba8(188, 188, 188)}}};
  scene.instances[0].materials = {{glm::vec3(1.0f), 0}};
  for (const glm::vec3& p : scene.meshes[0].positions) scene.meshes[0].uvs.emplace_back(0.5f * (p.x + 1.0f), 0.5f * (p.y + 1.0f));
  RenderOutput out = render_from_above(scene);
  // Texel centres (uv 1/4 and 3/4) show their texel alone.
  expect_hue(hue_at(out, -0.5f, -0.5f), {1, 0, 0}, "bottom left");
  expect_hue(hue_at(out, 0.5f, -0.5f), {0, 1, 0}, "bottom right");
  expect_hue(hue_at(out, -0.5f, 0.5f), {0, 0, 1}, "top left");

  // UVs past 1 repeat the image: shifted by whole images, the same colours.
  Scene shifted_scene = scene;
  for (glm::vec2& uv : shifted_scene.meshes[0].uvs) uv += glm::vec2(3.0f, -2.0f);
  const RenderOutput shifted = render_from_above(shifted_scene);
  for (size_t i = 0; i < out.combined.size(); ++i) ASSERT_NEAR(out.combined[i], shifted.combined[i], 1e-3f) << i;

  // sRGB 188 is linear 0.5: half the light a white texel gives.
  const size_t top_right = 4 * (size_t(kSize / 4) * kSize + 3 * kSize / 4) + 1;
  const float grey = out.combined[top_right];
  scene.textures[0].texels.assign(4, rgba8(255, 255, 255));
  const float white = render_from_above(scene).combined[top_right];
  EXPECT_NEAR(grey / white, 0.5f, 0.04f) << "texels are decoded from sRGB";
}

// A colour attribute is interpolated between the vertices and multiplies the
// base colour of the slots that take it; other slots ignore it.
TEST_F(MaterialsTest, VertexColoursMultiplyTheBaseColourOfSlotsThatTakeThem) {
  Scene scene = sheet_scene();
  const glm::vec3 yellow(1, 1, 0), cyan(0, 1, 1);
  scene.meshes[0].colors = {yellow, yellow, cyan, cyan};  // (bottom, bottom, top, top)
  Material magenta_by_vertex{glm::vec3(1, 0, 1)};
  magenta_by_vertex.vertex_color = true;
  scene.instances[0].materials = {magenta_by_vertex};
  RenderOutput out = render_from_above(scene);
  expect_hue(hue_at(out, 0.0f, -0.9f), {1, 0, 0.05f}, "bottom: magenta times yellow");
  expect_hue(hue_at(out, 0.0f, 0.9f), {0.05f, 0, 1}, "top: magenta times cyan");
  expect_hue(hue_at(out, 0.0f, 0.0f), {1, 0, 1}, "between: interpolated");

  // A slot that does not take the colours shows its own colour.
  scene.meshes[0].materials = {0, 1};
  scene.instances[0].materials = {magenta_by_vertex, {glm::vec3(0, 0.8f, 0)}};
  out = render_from_above(scene);
  expect_hue(hue_at(out, 0.5f, -0.8f), {1, 0, 0.1f}, "slot 0: by vertex");
  expect_hue(hue_at(out, -0.5f, 0.5f), {0, 1, 0}, "slot 1: its own colour");
}

TEST_F(MaterialsTest, BadMaterialInputIsRefused) {
  Scene scene = sheet_scene();
  scene.meshes[0].materials = {0};  // one slot index for two triangles
  EXPECT_THROW(GpuScene(context(), scene), Error);
  scene = sheet_scene();
  scene.instances[0].materials = {{glm::vec3(1.0f), 3}};  // no image 3
  EXPECT_THROW(GpuScene(context(), scene), Error);
  scene.textures = {{"short", 4, 4, std::vector<uint32_t>(5)}};  // 16 texels expected
  scene.instances[0].materials = {{glm::vec3(1.0f), 0}};
  EXPECT_THROW(GpuScene(context(), scene), Error);
  scene = sheet_scene();
  scene.meshes[0].uvs = {{0, 0}, {1, 0}};  // two UVs for four vertices
  EXPECT_THROW(GpuScene(context(), scene), Error);
  scene = sheet_scene();
  scene.meshes[0].colors = {glm::vec3(1.0f)};  // one colour for four vertices
  EXPECT_THROW(GpuScene(context(), scene), Error);
  scene.meshes[0].colors.assign(4, glm::vec3(1.0f, std::nanf(""), 0.0f));
  EXPECT_THROW(GpuScene(context(), scene), Error);
}

}  // namespace
}  // namespace rtsdf
