#pragma once
// The view and light several tests share: an orthographic camera straight
// down on x and y in [-2, 2], and a sun tilted 45 degrees towards +x, 5
// degrees wide (soft shadows a few pixels wide).
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "renderer.h"

namespace rtsdf::testing {

inline Camera top_view() {
  Camera camera;
  camera.world_to_view = glm::lookAt(glm::vec3(0, 0, 10), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
  camera.projection = glm::orthoRH_NO(-2.0f, 2.0f, -2.0f, 2.0f, 0.1f, 20.0f);
  camera.orthographic = true;
  return camera;
}

inline Light tilted_sun() {
  Light sun;
  sun.type = LightType::Sun;
  sun.direction = {float(std::sqrt(0.5)), 0, -float(std::sqrt(0.5))};
  sun.energy = 3.0f;
  sun.sun_angle = float(5.0 * M_PI / 180.0);
  return sun;
}

}  // namespace rtsdf::testing
