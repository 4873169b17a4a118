#pragma once
// A viewport: its own scene on the device and a renderer accumulating it
// progressively, one frame per draw. Here is decided what a change means
// for the image: the scene changes through update (KeptScene tells what
// changed, as for final renders) or the explicit sync, set_transforms and
// set_mesh; a draw
// whose view or settings differ from the last one's starts the
// accumulation afresh (carrying history over where temporal reuse is on,
// see Renderer::begin); an unchanged draw adds a frame until the image has
// converged and the fields have stopped refining, then does nothing.
#include <memory>
#include <vector>

#include "kept_scene.h"
#include "renderer.h"

namespace rtsdf {

// What a draw shows besides the scene.
struct View {
  Camera camera;
  std::vector<Light> lights;
  glm::vec3 ambient{0.0f};
  int width = 0, height = 0;
  bool operator==(const View& other) const;
  bool operator!=(const View& other) const { return !(*this == other); }
};

struct ViewportFrame {
  RenderOutput image;  // the accumulation so far (with the passes where temporal reuse is on)
  bool advanced = false;   // a frame was added by this draw
  bool converged = false;  // all samples in (or every tile converged) and the fields refined: further draws do nothing
  // The samples this frame's pixels stand for on average (with temporal reuse, history's too).
  double effective_samples = 0.0;
  // Wall time of the draw: starting afresh (the SDFs rebuilt after a change), the frame, the read-back.
  double begin_ms = 0.0, frame_ms = 0.0, read_ms = 0.0;
};

class Viewport {
 public:
  // Room the viewport's grids keep around the shadow casters, as a share of
  // their extent, so that an object moving a little keeps its grid and history.
  static constexpr float kGridSlack = 0.5f;
  // The settings a viewport draws with where its caller names none.
  static RenderSettings default_settings();

  Viewport(const vk::Context& context, std::shared_ptr<FieldCache> field_cache);

  // The scene as it is now: only what changed is uploaded (KeptScene::update).
  // Returns whether anything changed.
  bool update(const Scene& scene);
  // The whole scene uploaded afresh.
  void sync(const Scene& scene);
  // A transform for every instance, in sync's order.
  void set_transforms(const std::vector<glm::mat4>& object_to_world);
  // New vertex positions of one mesh (same vertex count and triangles).
  void set_mesh_positions(uint32_t mesh, const std::vector<glm::vec3>& positions);
  // New geometry of one mesh, in its place.
  void set_mesh(uint32_t mesh, Mesh geometry);
  // The next draw starts a new accumulation of the same view, as after a
  // change (a benchmark's single frames).
  void restart() { restart_ = true; }

  // One accumulation frame of `view`, at most. The viewport's policy
  // overrides `settings`: the fields keep their history from draw to draw
  // (the paper's frame-to-frame reuse) and are updated in every frame until
  // they converge.
  ViewportFrame draw(const View& view, const RenderSettings& settings);

  const Renderer& renderer() const { return renderer_; }

 private:
  Renderer renderer_;
  KeptScene scene_;
  bool scene_changed_ = true;  // since the last begin
  bool restart_ = false;
  bool drawn_ = false;
  View drawn_view_;
  RenderSettings drawn_settings_;
};

}  // namespace rtsdf
