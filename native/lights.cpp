#include "lights.h"

#include <cmath>

#include "error.h"

namespace rtsdf {

namespace {

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

gpu::GpuLight to_gpu(const Light& light) {
  if (!finite(light.position) || !finite(light.direction) || !finite(light.color) || !std::isfinite(light.energy) ||
      !std::isfinite(light.sun_angle) || !std::isfinite(light.radius) || !std::isfinite(light.spot_size) ||
      !std::isfinite(light.spot_blend))
    throw Error("a light has NaN or infinite parameters");
  if (light.energy < 0.0f || light.radius < 0.0f || light.sun_angle < 0.0f)
    throw Error("a light has a negative energy or size");
  const float pi = float(M_PI);
  const glm::vec3 direction =
      glm::length(light.direction) > 0.0f ? glm::normalize(light.direction) : glm::vec3(0.0f, 0.0f, -1.0f);
  gpu::GpuLight out{};
  out.direction = glm::vec4(direction, light.radius);
  out.position = glm::vec4(light.position, 0.0f);
  // Measured with Cycles here: a white diffuse plane facing a sun of strength S
  // renders S / pi; at distance r from a point light of power P it renders
  // P / (4 pi r^2) / pi, and so does a spot inside its cone; on the axis of an
  // area light of power P (any size) it renders P / (4 pi r^2): intensity P / 4,
  // falling off with the cosine off the axis (one-sided).
  switch (light.type) {
    case LightType::Sun:
      out.position.w = float(gpu::kLightSun);
      out.radiance = glm::vec4(light.color * light.energy / pi, 0.0f);
      out.direction.w = std::tan(0.5f * std::min(light.sun_angle, pi * 0.99f));
      break;
    case LightType::Point:
    case LightType::Spot:
      out.position.w = float(light.type == LightType::Point ? gpu::kLightPoint : gpu::kLightSpot);
      out.radiance = glm::vec4(light.color * light.energy / (4.0f * pi * pi), 0.0f);
      if (light.type == LightType::Spot) {
        const float cos_edge = std::cos(0.5f * std::min(light.spot_size, pi));
        out.spot = glm::vec4(cos_edge, std::max((1.0f - cos_edge) * light.spot_blend, 1e-4f), 0.0f, 0.0f);
      } else {
        out.spot = glm::vec4(-2.0f, 1.0f, 0.0f, 0.0f);
      }
      break;
    case LightType::Area:
      out.position.w = float(gpu::kLightArea);
      out.radiance = glm::vec4(light.color * light.energy / (4.0f * pi), 0.0f);
      out.spot = glm::vec4(-2.0f, 1.0f, 1.0f, 0.0f);
      break;
  }
  out.spot.w = light.casts_shadow ? 0.0f : 1.0f;
  return out;
}

std::vector<gpu::GpuLight> to_gpu(const std::vector<Light>& lights) {
  std::vector<gpu::GpuLight> out;
  for (const Light& light : lights) out.push_back(to_gpu(light));
  return out;
}

}  // namespace rtsdf
