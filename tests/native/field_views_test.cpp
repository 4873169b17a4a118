// The views of the distance fields (FieldView) on the bundled CAD sample
// over a ground: each draws something (not an empty image) and something
// other than the shaded image; the slice view shows negative distances
// (blue) where it cuts through the part.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "mesh_import.h"
#include "reference/shapes.h"
#include "renderer.h"
#include "vulkan_test.h"

namespace rtsdf {
namespace {

constexpr int kWidth = 96, kHeight = 64;

class FieldViewsTest : public testing::VulkanTest {};

double mean_abs_difference(const std::vector<float>& a, const std::vector<float>& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); i += 4)
    for (int c = 0; c < 3; ++c) sum += std::abs(double(a[i + c]) - double(b[i + c]));
  return sum / double(a.size() / 4 * 3);
}

double spread(const std::vector<float>& image) {  // standard deviation of the pixels' red, green and blue
  double sum = 0.0, square = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < image.size(); i += 4)
    for (int c = 0; c < 3; ++c) sum += image[i + c], square += double(image[i + c]) * image[i + c], ++n;
  return std::sqrt(std::max(square / n - (sum / n) * (sum / n), 0.0));
}

TEST_F(FieldViewsTest, EachViewOfTheCadSampleDrawsSomethingElseThanTheImage) {
  Scene scene = import_scene(testing::test_mesh_path());
  const Bounds part = scene.world_bounds();
  const glm::vec3 centre = 0.5f * (part.lo + part.hi);
  const float size = glm::length(part.extent());
  scene.meshes.push_back(reference::sheet({centre.x - 2 * size, centre.y - 2 * size},
                                          {centre.x + 2 * size, centre.y + 2 * size}, part.lo.z));
  scene.instances.push_back({1, glm::mat4(1.0f), glm::vec3(0.8f)});
  GpuScene gpu_scene(context(), scene);
  Camera camera;
  camera.world_to_view = glm::lookAt(centre + glm::vec3(0.6f, -1.0f, 0.8f) * size, centre, glm::vec3(0, 0, 1));
  camera.projection = glm::perspective(0.7f, float(kWidth) / kHeight, 0.01f * size, 10.0f * size);
  Light sun;
  sun.type = LightType::Sun;
  sun.direction = glm::normalize(glm::vec3(0.3f, 0.4f, -1.0f));
  sun.energy = 3.0f;
  sun.sun_angle = 0.05f;
  RenderSettings settings;
  settings.coarse_resolution = 32;
  settings.fine_resolution = 64;
  settings.samples = 2;
  settings.exact_rays = 4;
  settings.field_view_height = centre.z;
  Renderer renderer(context());
  const std::vector<float> shaded =
      renderer.render(gpu_scene, camera, {sun}, glm::vec3(0.1f), kWidth, kHeight, settings).combined;
  for (FieldView view : {FieldView::DistanceSlice, FieldView::MarchSteps, FieldView::FieldResolution,
                         FieldView::ExactRays}) {
    settings.field_view = view;
    const std::vector<float> image =
        renderer.render(gpu_scene, camera, {sun}, glm::vec3(0.1f), kWidth, kHeight, settings).combined;
    const double difference = mean_abs_difference(image, shaded);
    std::printf("%s: mean |view - image| %.4f, spread %.4f\n", field_view_name(view), difference, spread(image));
    EXPECT_GT(spread(image), 0.02) << field_view_name(view) << ": not an empty image";
    EXPECT_GT(difference, view == FieldView::ExactRays ? 0.002 : 0.02) << field_view_name(view);
    if (view == FieldView::DistanceSlice) {
      size_t inside = 0;  // (blue: the slice inside the part)
      for (size_t i = 0; i < image.size(); i += 4) inside += image[i + 2] > 0.5f && image[i] < 0.2f;
      EXPECT_GT(inside, 10u) << "the slice through the part shows its inside";
    }
  }
  EXPECT_THROW(parse_field_view("heat"), Error);
  EXPECT_STREQ(field_view_name(parse_field_view("march_steps")), "march_steps");
}

}  // namespace
}  // namespace rtsdf
