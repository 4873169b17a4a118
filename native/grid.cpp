#include "grid.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <string>

#include "error.h"
#include "shaders/shared.h"

namespace rtsdf {

glm::ivec3 bricks_of(glm::ivec3 dims) {
  // The cells between texels, [0, dims - 2] per axis, 7 to a brick.
  return glm::max(dims - 2, glm::ivec3(0)) / int(gpu::kBrickCells) + 1;
}

glm::mat4 GridSpec::world_to_voxel() const {
  return glm::scale(glm::mat4(1.0f), glm::vec3(1.0f / voxel_size)) * glm::translate(glm::mat4(1.0f), -origin);
}


int margin_voxels(int resolution) { return resolution >= 32 ? 3 : 1; }

GridSpec fit_grid(const Bounds& bounds, int resolution) {
  const int max_resolution = int(gpu::kMaxGridResolution);
  if (resolution < 4 || resolution > max_resolution)
    throw Error("resolution " + std::to_string(resolution) + " is out of range: use 4 to " +
                std::to_string(max_resolution) + " voxels on the longest axis");
  const int margin = margin_voxels(resolution);
  glm::vec3 extent = bounds.extent();
  float longest = std::max(extent.x, std::max(extent.y, extent.z));
  GridSpec grid;
  grid.voxel_size = longest / float(resolution - 2 * margin);
  for (int a = 0; a < 3; ++a)
    grid.dims[a] = std::clamp(int(std::ceil(extent[a] / grid.voxel_size - 1e-4f)) + 2 * margin, 1, resolution);
  glm::vec3 center = 0.5f * (bounds.lo + bounds.hi);
  grid.origin = center - 0.5f * glm::vec3(grid.dims) * grid.voxel_size;
  return grid;
}

GridSpec keep_or_fit_grid(const GridSpec* current, const Bounds& bounds, int resolution, float slack) {
  const GridSpec tight = fit_grid(bounds, resolution);
  if (slack <= 0.0f) return tight;
  if (current && current->voxel_count() > 0) {
    const float margin =
        float(margin_voxels(std::max(current->dims.x, std::max(current->dims.y, current->dims.z)))) * current->voxel_size;
    const glm::vec3 lo = current->origin + margin;
    const glm::vec3 hi = current->origin + glm::vec3(current->dims) * current->voxel_size - margin;
    if (glm::all(glm::greaterThanEqual(bounds.lo, lo)) && glm::all(glm::lessThanEqual(bounds.hi, hi)) &&
        current->voxel_size <= tight.voxel_size * (1.0f + 2.0f * slack))
      return *current;
  }
  // The same room along every axis: what moves or deforms (a walking
  // character's limbs) goes as far along the bounds' thin axes as along their
  // long one, and room in proportion left a thin axis none to speak of.
  const glm::vec3 extent = bounds.extent();
  const glm::vec3 room(0.5f * slack * std::max(extent.x, std::max(extent.y, extent.z)));
  return fit_grid(Bounds{bounds.lo - room, bounds.hi + room}, resolution);
}

}  // namespace rtsdf
