#include "kept_scene.h"

#include "error.h"

namespace rtsdf {

bool KeptScene::same_structure(const Scene& scene) const {
  if (scene.meshes.size() != kept_.meshes.size() || scene.instances.size() != kept_.instances.size() ||
      scene.textures != kept_.textures)
    return false;
  for (size_t m = 0; m < kept_.meshes.size(); ++m) {
    const Mesh &a = scene.meshes[m], &b = kept_.meshes[m];
    if (a.materials != b.materials || a.uvs != b.uvs || a.colors != b.colors) return false;
  }
  for (size_t i = 0; i < kept_.instances.size(); ++i) {
    const Instance &a = scene.instances[i], &b = kept_.instances[i];
    if (a.mesh != b.mesh || a.base_color != b.base_color || a.materials != b.materials ||
        a.casts_shadow != b.casts_shadow || a.visible_to_camera != b.visible_to_camera || a.holdout != b.holdout)
      return false;
  }
  return true;
}

SceneUpdate KeptScene::update(const Scene& scene) {
  if (!gpu_scene_ || !same_structure(scene)) {
    upload(scene);
    return SceneUpdate::Uploaded;
  }
  bool changed = false;
  for (size_t m = 0; m < kept_.meshes.size(); ++m) {
    const Mesh &now = scene.meshes[m], &held = kept_.meshes[m];
    // (Blender's smooth normals evaluated again differ in their last bits:
    // new normals alone reach the rasterizer only, see GpuScene::set_mesh)
    if (now.positions != held.positions || now.indices != held.indices || now.normals != held.normals) {
      set_mesh(uint32_t(m), now);
      changed = true;
    }
  }
  std::vector<glm::mat4> transforms;
  bool moved = false;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    transforms.push_back(scene.instances[i].object_to_world);
    moved = moved || transforms.back() != kept_.instances[i].object_to_world;
  }
  if (moved) set_transforms(transforms);
  return changed || moved ? SceneUpdate::InPlace : SceneUpdate::Unchanged;
}

void KeptScene::upload(const Scene& scene) {
  gpu_scene_.reset();  // (frees the old one first)
  gpu_scene_ = std::make_unique<GpuScene>(context_, scene);
  kept_ = scene;
}

void KeptScene::clear() {
  gpu_scene_.reset();
  kept_ = {};
}

GpuScene& KeptScene::gpu() {
  if (!gpu_scene_) throw Error("there is no scene on the device: sync it first");
  return *gpu_scene_;
}

void KeptScene::set_transforms(const std::vector<glm::mat4>& object_to_world) {
  gpu().set_transforms(object_to_world);
  for (size_t i = 0; i < kept_.instances.size() && i < object_to_world.size(); ++i)
    kept_.instances[i].object_to_world = object_to_world[i];
}

void KeptScene::set_mesh_positions(uint32_t mesh, const std::vector<glm::vec3>& positions) {
  gpu().set_mesh_positions(mesh, positions);
  kept_.meshes[mesh].positions = positions;
}

void KeptScene::set_mesh(uint32_t mesh, Mesh geometry) {
  GpuScene& scene = gpu();
  scene.set_mesh(mesh, geometry);
  kept_.meshes[mesh] = scene.scene().meshes[mesh];  // (as the device scene holds it: its name kept)
}

}  // namespace rtsdf
