#include "gpu_scene.h"

namespace rtsdf {

GpuScene::GpuScene(const vk::Context& context, const Scene& scene) {
  scene.validate();
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  for (const Mesh& mesh : scene.meshes) {
    meshes_.push_back({uint32_t(indices.size()), uint32_t(positions.size()), uint32_t(mesh.triangle_count())});
    positions.insert(positions.end(), mesh.positions.begin(), mesh.positions.end());
    indices.insert(indices.end(), mesh.indices.begin(), mesh.indices.end());
  }
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "positions are uploaded as packed floats");
  positions_ = vk::upload_buffer(context, positions.data(), positions.size() * sizeof(glm::vec3),
                                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  indices_ = vk::upload_buffer(context, indices.data(), indices.size() * sizeof(uint32_t),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  instances_ = scene.instances;
  bounds_ = scene.world_bounds();
  triangle_count_ = scene.triangle_count();
}

}  // namespace rtsdf
