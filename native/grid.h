#pragma once
// The voxel grid an SDF lives on: cubic voxels fitted to the scene's bounds.
#include <glm/glm.hpp>

#include "scene.h"

namespace rtsdf {

struct GridSpec {
  glm::vec3 origin{0.0f};  // world position of the grid's minimum corner
  float voxel_size = 1.0f;  // world units
  glm::ivec3 dims{0};

  size_t voxel_count() const { return size_t(dims.x) * dims.y * dims.z; }
  // Voxel i spans [i, i+1) in voxel space; its centre is at i + 0.5.
  glm::vec3 voxel_center(glm::ivec3 voxel) const { return origin + (glm::vec3(voxel) + 0.5f) * voxel_size; }
  glm::mat4 world_to_voxel() const;
  // The same bounds with `factor` times as many voxels per axis.
};

// Empty voxels kept around the scene's bounds on every side, so the band
// around surfaces near the bounds is inside the grid.
int margin_voxels(int resolution);

// Fits a grid with `resolution` voxels on the longest axis around `bounds`
// plus margin_voxels(resolution) on each side. Throws rtsdf::Error for a
// resolution outside [4, 1024].
GridSpec fit_grid(const Bounds& bounds, int resolution);

// The grid for geometry within `bounds` that moves or deforms: `current`
// (may be null) while the geometry stays inside it, clear of its margin,
// and it is not much coarser than a tight fit; otherwise a grid fitted with
// `slack` x the bounds' longest extent of room around them, along every axis
// (0: tight), so that it can stay for a while. A grid that stays keeps its fine SDF's history.
GridSpec keep_or_fit_grid(const GridSpec* current, const Bounds& bounds, int resolution, float slack);

// The bricks along each axis of a fine grid of `dims` texels (8^3 texels a
// brick, sharing faces: see kBrickTexels in shaders/shared.h).
glm::ivec3 bricks_of(glm::ivec3 dims);

}  // namespace rtsdf
