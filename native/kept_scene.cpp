#include "kept_scene.h"

namespace rtsdf {

bool KeptScene::same_shapes(const Scene& scene) const {
  if (scene.meshes.size() != kept_.meshes.size() || scene.instances.size() != kept_.instances.size() ||
      scene.textures != kept_.textures)
    return false;
  for (size_t m = 0; m < kept_.meshes.size(); ++m) {
    const Mesh &a = scene.meshes[m], &b = kept_.meshes[m];
    if (a.positions != b.positions || a.indices != b.indices || a.materials != b.materials || a.uvs != b.uvs ||
        a.colors != b.colors)
      return false;
  }
  for (size_t i = 0; i < kept_.instances.size(); ++i) {
    const Instance &a = scene.instances[i], &b = kept_.instances[i];
    if (a.mesh != b.mesh || a.base_color != b.base_color || a.materials != b.materials ||
        a.casts_shadow != b.casts_shadow || a.visible_to_camera != b.visible_to_camera || a.holdout != b.holdout)
      return false;
  }
  return true;
}

bool KeptScene::update(const Scene& scene) {
  if (gpu_scene_ && same_shapes(scene)) {
    // (smooth normals evaluated again differ in their last bits: new normals reach the rasterizer only)
    for (size_t m = 0; m < kept_.meshes.size(); ++m)
      if (scene.meshes[m].normals != kept_.meshes[m].normals) {
        gpu_scene_->set_mesh(uint32_t(m), scene.meshes[m]);
        kept_.meshes[m].normals = scene.meshes[m].normals;
      }
    std::vector<glm::mat4> transforms;
    for (const Instance& instance : scene.instances) transforms.push_back(instance.object_to_world);
    gpu_scene_->set_transforms(transforms);
    return true;
  }
  gpu_scene_.reset();  // (frees the old one first)
  gpu_scene_ = std::make_unique<GpuScene>(context_, scene);
  kept_ = scene;
  return false;
}

void KeptScene::clear() {
  gpu_scene_.reset();
  kept_ = {};
}

}  // namespace rtsdf
