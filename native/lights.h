#pragma once
// Lights as Blender describes them, and their conversion to what the shading
// pass reads, in the units of Cycles' direct light.
#include <glm/glm.hpp>
#include <vector>

#include "shaders/shared.h"

namespace rtsdf {

enum class LightType { Sun, Point, Spot, Area };

struct Light {
  LightType type = LightType::Sun;
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // where it shines (Blender: the object's -Z)
  glm::vec3 color{1.0f};
  float energy = 1.0f;      // sun: strength in W/m^2; others: power in W
  float sun_angle = 0.0f;   // sun: angular diameter in radians
  float radius = 0.0f;      // point, spot: shadow_soft_size; area: half the size
  float spot_size = 0.0f;   // spot: full cone angle in radians
  float spot_blend = 0.0f;  // spot: 0..1
  bool casts_shadow = true;  // off: lights every surface it faces, through anything (Blender's Cast Shadow)
};

// Throws rtsdf::Error for NaN values or negative energies and sizes.
gpu::GpuLight to_gpu(const Light& light);
std::vector<gpu::GpuLight> to_gpu(const std::vector<Light>& lights);

}  // namespace rtsdf
