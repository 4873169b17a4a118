#pragma once
// A scene kept on the device between final renders (Blender's persistent
// data), brought up to date with each newer description of it.
#include <memory>
#include <vector>

#include "gpu_scene.h"
#include "scene.h"

namespace rtsdf {

class KeptScene {
 public:
  explicit KeptScene(const vk::Context& context) : context_(context) {}

  // Where `scene` has the shapes of the one on the device (the same
  // vertices, triangles, material slots, UVs and colours; instances of the
  // same meshes with the same materials and flags; the same images), only
  // its transforms and changed normals are uploaded and the device scene
  // keeps its identity, so a renderer keeps its fields and history. Anything
  // else uploads `scene` afresh. Returns whether the scene was updated in place.
  bool update(const Scene& scene);
  // Frees the device scene (the next update uploads afresh).
  void clear();
  // The scene on the device; call update first.
  GpuScene& gpu() { return *gpu_scene_; }

 private:
  bool same_shapes(const Scene& scene) const;

  const vk::Context& context_;
  std::unique_ptr<GpuScene> gpu_scene_;
  Scene kept_;  // what was uploaded, with the normals since
};

}  // namespace rtsdf
