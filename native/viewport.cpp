#include "viewport.h"

#include <chrono>

#include "error.h"

namespace rtsdf {

namespace {

bool same_light(const Light& a, const Light& b) {
  return a.type == b.type && a.position == b.position && a.direction == b.direction && a.color == b.color &&
         a.energy == b.energy && a.sun_angle == b.sun_angle && a.radius == b.radius && a.spot_size == b.spot_size &&
         a.spot_blend == b.spot_blend && a.casts_shadow == b.casts_shadow;
}

double ms_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

}  // namespace

bool View::operator==(const View& other) const {
  if (lights.size() != other.lights.size()) return false;
  for (size_t i = 0; i < lights.size(); ++i)
    if (!same_light(lights[i], other.lights[i])) return false;
  return camera.world_to_view == other.camera.world_to_view && camera.projection == other.camera.projection &&
         camera.orthographic == other.camera.orthographic && ambient == other.ambient && width == other.width &&
         height == other.height;
}

RenderSettings Viewport::default_settings() {
  RenderSettings settings;
  settings.grid_slack = kGridSlack;
  return settings;
}

Viewport::Viewport(const vk::Context& context, std::shared_ptr<FieldCache> field_cache)
    : renderer_(context, std::move(field_cache)), scene_(context) {}

bool Viewport::update(const Scene& scene) {
  const bool changed = scene_.update(scene) != SceneUpdate::Unchanged;
  scene_changed_ = scene_changed_ || changed;
  return changed;
}

void Viewport::sync(const Scene& scene) {
  scene_.upload(scene);
  scene_changed_ = true;
}

void Viewport::set_transforms(const std::vector<glm::mat4>& object_to_world) {
  scene_.set_transforms(object_to_world);
  scene_changed_ = true;
}

void Viewport::set_mesh_positions(uint32_t mesh, const std::vector<glm::vec3>& positions) {
  scene_.set_mesh_positions(mesh, positions);
  scene_changed_ = true;
}

void Viewport::set_mesh(uint32_t mesh, Mesh geometry) {
  scene_.set_mesh(mesh, std::move(geometry));
  scene_changed_ = true;
}

ViewportFrame Viewport::draw(const View& view, const RenderSettings& requested) {
  if (!scene_.has_scene()) throw Error("draw: call sync first");
  RenderSettings settings = requested;
  settings.keep_history = true;
  settings.sdf_updates = 0;
  using Clock = std::chrono::steady_clock;
  ViewportFrame frame;
  const Clock::time_point start = Clock::now();
  if (scene_changed_ || restart_ || !drawn_ || view != drawn_view_ || !same_settings(settings, drawn_settings_)) {
    renderer_.begin(scene_.gpu(), view.camera, view.lights, view.ambient, view.width, view.height, settings, scene_changed_);
    scene_changed_ = restart_ = false;
    drawn_ = true;
    drawn_view_ = view;
    drawn_settings_ = settings;
  }
  const Clock::time_point begun = Clock::now();
  if (!renderer_.converged()) {
    renderer_.add_frame();
    frame.advanced = true;
  }
  const Clock::time_point added = Clock::now();
  frame.image = renderer_.read(/*passes=*/settings.temporal_reuse);  // (the samples per pixel: the passes' third)
  frame.begin_ms = ms_between(start, begun);
  frame.frame_ms = ms_between(begun, added);
  frame.read_ms = ms_between(added, Clock::now());
  frame.converged = renderer_.converged();
  frame.effective_samples = settings.temporal_reuse ? frame.image.effective_samples : double(frame.image.samples_done);
  return frame;
}

}  // namespace rtsdf
