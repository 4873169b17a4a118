// Where a change is decided: the settings compared over their one key list,
// a viewport restarting its accumulation only when its view, settings or
// scene changed (or when asked to), and a kept scene updated in place only when its shapes
// are the same.
#include <cmath>
#include <type_traits>
#include <glm/gtc/matrix_transform.hpp>

#include "error.h"

#include "kept_scene.h"
#include "reference/shapes.h"
#include "viewport.h"
#include "vulkan_test.h"

namespace rtsdf {
namespace {

TEST(SameSettings, EveryNamedSettingAndTheMethodCount) {
  const RenderSettings base;
  EXPECT_TRUE(same_settings(base, base));
  int keys = 0;
  visit_settings(const_cast<RenderSettings&>(base), [&](const char* key, const auto&) {
    RenderSettings changed = base;
    int index = 0;
    visit_settings(changed, [&](const char*, auto& value) {
      if (index++ != keys) return;
      if constexpr (std::is_same_v<std::decay_t<decltype(value)>, bool>)
        value = !value;  // (a setting on by default, too)
      else
        value = value + 1;
    });
    EXPECT_FALSE(same_settings(base, changed)) << key;
    keys++;
  });
  EXPECT_GT(keys, 15);
  RenderSettings method = base, view = base, history = base;
  method.shadow_method = ShadowMethod::CsmEvsm;
  view.field_view = FieldView::MarchSteps;
  history.keep_history = !base.keep_history;
  EXPECT_FALSE(same_settings(base, method));
  EXPECT_FALSE(same_settings(base, view));
  EXPECT_FALSE(same_settings(base, history));
}

class ViewportTest : public testing::VulkanTest {
 protected:
  static Scene sphere_on_ground() {
    Scene scene;
    scene.meshes.push_back(reference::uv_sphere({0, 0, 1}, 1.0f, 24));
    scene.meshes.push_back(reference::box({-4, -4, -0.2f}, {4, 4, 0}));
    scene.instances.push_back({0, glm::mat4(1.0f)});
    scene.instances.push_back({1, glm::mat4(1.0f)});
    return scene;
  }
  static View top_view() {
    View view;
    view.camera.world_to_view = glm::lookAt(glm::vec3(0, -6, 8), glm::vec3(0), glm::vec3(0, 0, 1));
    view.camera.projection = glm::perspectiveRH_NO(0.8f, 1.0f, 0.1f, 50.0f);
    Light sun;
    sun.direction = glm::normalize(glm::vec3(0.3f, 0.2f, -1.0f));
    sun.sun_angle = 0.05f;
    view.lights = {sun};
    view.ambient = glm::vec3(0.1f);
    view.width = view.height = 32;
    return view;
  }
};

TEST_F(ViewportTest, OnlyAChangedViewSettingOrSceneRestartsTheAccumulation) {
  Viewport viewport(context(), nullptr);
  viewport.sync(sphere_on_ground());
  RenderSettings settings = Viewport::default_settings();
  settings.samples = 2;
  settings.coarse_resolution = 16;
  settings.fine_resolution = 32;
  const View view = top_view();
  ViewportFrame frame;
  for (int draw = 0; draw < 64 && !frame.converged; ++draw) frame = viewport.draw(view, settings);
  ASSERT_TRUE(frame.converged);
  EXPECT_FALSE(viewport.draw(view, settings).advanced) << "converged, nothing changed: no work";

  View moved = view;
  moved.camera.world_to_view[3][2] -= 1e-5f;
  frame = viewport.draw(moved, settings);
  EXPECT_TRUE(frame.advanced);
  EXPECT_EQ(frame.image.samples_done, 1) << "a moved camera starts afresh";

  frame = viewport.draw(moved, settings);
  EXPECT_EQ(frame.image.samples_done, 2) << "the same view goes on";
  settings.shadow_epsilon *= 1.5f;
  EXPECT_EQ(viewport.draw(moved, settings).image.samples_done, 1) << "a changed setting starts afresh";

  viewport.set_transforms({glm::translate(glm::mat4(1.0f), glm::vec3(0.1f, 0, 0)), glm::mat4(1.0f)});
  EXPECT_EQ(viewport.draw(moved, settings).image.samples_done, 1) << "a moved object starts afresh";
  EXPECT_EQ(viewport.draw(moved, settings).image.samples_done, 2);
  viewport.restart();
  EXPECT_EQ(viewport.draw(moved, settings).image.samples_done, 1) << "restart() starts afresh";
}

// A bad update (NaN positions, a NaN transform) is refused with
// rtsdf::Error and leaves the viewport drawing the scene it held; a mesh
// emptied by its modifiers is no error: it casts and shows nothing.
TEST_F(ViewportTest, ABadUpdateIsRefusedAndTheViewportDrawsOn) {
  Viewport viewport(context(), nullptr);
  const Scene good = sphere_on_ground();
  viewport.update(good);
  RenderSettings settings = Viewport::default_settings();
  settings.samples = 1;
  settings.coarse_resolution = 16;
  settings.fine_resolution = 32;
  viewport.draw(top_view(), settings);

  Scene nan_positions = good;
  nan_positions.meshes[0].positions[3].x = std::nanf("");
  EXPECT_THROW(viewport.update(nan_positions), Error);
  Scene nan_transform = good;
  nan_transform.instances[0].object_to_world[3][0] = std::nanf("");
  EXPECT_THROW(viewport.update(nan_transform), Error);

  EXPECT_FALSE(viewport.update(good)) << "the scene held is the good one";
  for (float v : viewport.draw(top_view(), settings).image.combined) ASSERT_TRUE(std::isfinite(v));

  Scene empty_mesh = good;
  empty_mesh.meshes[0].positions.clear();
  empty_mesh.meshes[0].indices.clear();
  EXPECT_TRUE(viewport.update(empty_mesh));
  for (float v : viewport.draw(top_view(), settings).image.combined) ASSERT_TRUE(std::isfinite(v));
}

TEST_F(ViewportTest, AKeptSceneUpdatesInPlaceWhereItsStructureStays) {
  KeptScene kept(context());
  Scene scene = sphere_on_ground();
  EXPECT_EQ(kept.update(scene), SceneUpdate::Uploaded) << "the first update uploads";
  const uint64_t id = kept.gpu().id();
  EXPECT_EQ(kept.update(scene), SceneUpdate::Unchanged);

  scene.instances[0].object_to_world = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, 0, 0));
  EXPECT_EQ(kept.update(scene), SceneUpdate::InPlace) << "a moved instance: transforms only";
  EXPECT_EQ(kept.gpu().id(), id);
  EXPECT_EQ(kept.gpu().instances()[0].object_to_world[3][0], 0.5f);

  const uint64_t sphere_version = kept.gpu().mesh_version(0), ground_version = kept.gpu().mesh_version(1);
  for (glm::vec3& p : scene.meshes[0].positions) p *= 1.1f;
  EXPECT_EQ(kept.update(scene), SceneUpdate::InPlace) << "a deformed mesh, in place";
  EXPECT_EQ(kept.gpu().id(), id);
  EXPECT_NE(kept.gpu().mesh_version(0), sphere_version) << "the deformed mesh is reshaped";
  EXPECT_EQ(kept.gpu().mesh_version(1), ground_version) << "the other is not";
  EXPECT_EQ(kept.update(scene), SceneUpdate::Unchanged) << "the same again";

  scene.instances[1].casts_shadow = false;
  EXPECT_EQ(kept.update(scene), SceneUpdate::Uploaded) << "another flag: uploaded afresh";
  EXPECT_NE(kept.gpu().id(), id);
}

}  // namespace
}  // namespace rtsdf
