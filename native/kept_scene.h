#pragma once
// A scene kept on the device between renders or draws, brought up to date
// with each newer description of it by uploading only what changed: the one
// place that tells, for final renders with persistent data and for the
// viewport alike, what changed in a scene.
#include <memory>
#include <vector>

#include "gpu_scene.h"
#include "scene.h"

namespace rtsdf {

enum class SceneUpdate {
  Unchanged,  // nothing to upload
  InPlace,    // transforms, or some meshes' geometry or normals, updated in the scene on the device
  Uploaded,   // uploaded afresh (a new scene: renderers start their fields and history anew)
};

class KeptScene {
 public:
  explicit KeptScene(const vk::Context& context) : context_(context) {}

  // Brings the device scene up to `scene`. Where the structure is the same
  // (as many meshes and instances; each instance of the same mesh with the
  // same materials and flags; each mesh with the same material slots, UVs
  // and colours; the same images), the device scene keeps its identity, so
  // renderers keep their fields and history: meshes whose positions,
  // triangles or normals differ are replaced in place (GpuScene::set_mesh:
  // only a reshaped mesh's field is rebuilt) and changed transforms are
  // uploaded. Anything else uploads `scene` afresh.
  SceneUpdate update(const Scene& scene);
  // Uploads `scene` afresh, whatever is kept.
  void upload(const Scene& scene);
  // Frees the device scene (the next update uploads afresh).
  void clear();

  // Changes known to the caller, applied without comparing (see GpuScene).
  void set_transforms(const std::vector<glm::mat4>& object_to_world);
  void set_mesh_positions(uint32_t mesh, const std::vector<glm::vec3>& positions);
  void set_mesh(uint32_t mesh, Mesh geometry);

  bool has_scene() const { return gpu_scene_ != nullptr; }
  // The scene on the device: call update or upload first.
  GpuScene& gpu();

 private:
  bool same_structure(const Scene& scene) const;

  const vk::Context& context_;
  std::unique_ptr<GpuScene> gpu_scene_;
  Scene kept_;  // what the device scene holds now
};

}  // namespace rtsdf
