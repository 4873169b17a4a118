#pragma once
// The analytic soft shadow of a sphere lit by a disk-shaped light (a sun, or
// a spherical light seen from the receiver), and where a rendered shadow's
// visibility crosses 10%, 50% and 90% along a line.
#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

namespace rtsdf::testing {

// Share of a disk of angular radius a (the light) hidden by a disk of radius r
// (the sphere) whose centre is d away (small angles: planar disks).
inline double hidden_share(double a, double r, double d) {
  if (d >= a + r) return 0.0;
  if (d <= std::abs(r - a)) return r >= a ? 1.0 : (r * r) / (a * a);
  double alpha = std::acos((d * d + a * a - r * r) / (2 * d * a));
  double beta = std::acos((d * d + r * r - a * a) / (2 * d * r));
  double lens = a * a * (alpha - std::sin(2 * alpha) / 2) + r * r * (beta - std::sin(2 * beta) / 2);
  return lens / (M_PI * a * a);
}

// Share of a light of angular radius `light_radius` in direction `to_light`
// (unit) seen from `point` past a sphere (`center`, `radius`).
inline double sphere_visibility(glm::dvec3 point, glm::dvec3 to_light, double light_radius, glm::dvec3 center,
                                double radius) {
  glm::dvec3 to_center = center - point;
  double d = glm::length(to_center);
  double offset = std::acos(std::clamp(glm::dot(to_center / d, to_light), -1.0, 1.0));
  return 1.0 - hidden_share(light_radius, std::asin(radius / d), offset);
}

struct Profile {
  double x10 = 0, x50 = 0, x90 = 0;  // where visibility crosses 0.1, 0.5, 0.9 going outwards
  double width() const { return x90 - x10; }
};

// Scans x from `from` to `to` (out of the shadow into the light).
template <typename F>
Profile profile(F&& visibility, double from, double step, double to = 1.9) {
  Profile p;
  bool f10 = false, f50 = false, f90 = false;
  for (double x = from; x < to; x += step) {
    double v = visibility(x);
    if (!f10 && v >= 0.1) p.x10 = x, f10 = true;
    if (!f50 && v >= 0.5) p.x50 = x, f50 = true;
    if (!f90 && v >= 0.9) p.x90 = x, f90 = true;
  }
  return p;
}

}  // namespace rtsdf::testing
