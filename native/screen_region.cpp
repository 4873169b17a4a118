#include "screen_region.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rtsdf {

PixelRect PixelRect::united(const PixelRect& other) const {
  if (is_empty()) return other;
  if (other.is_empty()) return *this;
  return {glm::min(lo, other.lo), glm::max(hi, other.hi)};
}

PixelRect PixelRect::intersected(const PixelRect& other) const {
  const PixelRect both{glm::max(lo, other.lo), glm::min(hi, other.hi)};
  return both.is_empty() ? PixelRect{} : both;
}

PixelRect PixelRect::grown(int pixels, glm::ivec2 size) const {
  if (is_empty()) return *this;
  return {glm::max(lo - pixels, glm::ivec2(0)), glm::min(hi + pixels, size)};
}

PixelRect project_hull(const glm::mat4& world_to_clip, glm::ivec2 size, const std::vector<glm::vec3>& points) {
  const PixelRect whole = PixelRect::whole(size);
  glm::vec2 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
  for (const glm::vec3& p : points) {
    const glm::vec4 clip = world_to_clip * glm::vec4(p, 1.0f);
    // (at or behind the camera's plane, a point projects nowhere useful: its
    // hull's edges towards it cross the screen's sides)
    if (!(clip.w > 1e-6f * std::max(std::abs(clip.x), std::abs(clip.y)) && clip.w > 0.0f)) return whole;
    const glm::vec2 pixel = (glm::vec2(clip) / clip.w + 1.0f) * 0.5f * glm::vec2(size);
    if (!std::isfinite(pixel.x) || !std::isfinite(pixel.y)) return whole;
    lo = glm::min(lo, pixel);
    hi = glm::max(hi, pixel);
  }
  if (points.empty()) return {};
  // (pixel i's centre is at i + 0.5; a pixel to spare on each side for rounding)
  const glm::vec2 limit(float(size.x) + 2.0f, float(size.y) + 2.0f);
  const glm::ivec2 first(glm::floor(glm::clamp(lo, glm::vec2(-2.0f), limit)) - 1.0f);
  const glm::ivec2 last(glm::ceil(glm::clamp(hi, glm::vec2(-2.0f), limit)) + 1.0f);
  const PixelRect rect{glm::max(first, glm::ivec2(0)), glm::min(last, size)};
  return rect.is_empty() ? PixelRect{} : rect;
}

namespace {

std::vector<glm::vec3> corners(glm::vec3 lo, glm::vec3 hi) {
  std::vector<glm::vec3> points;
  for (int k = 0; k < 8; ++k) points.push_back(glm::vec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z));
  return points;
}

float farthest_corner(const Bounds& box, glm::vec3 from) {
  float farthest = 0.0f;
  for (const glm::vec3& c : corners(box.lo, box.hi)) farthest = std::max(farthest, glm::distance(c, from));
  return farthest;
}

// The points whose path to `light` crosses the box lo, hi grown by the
// light's cone there (light_path_crosses_change), within `visible`: the
// corners of a convex hull that holds them; empty when every point may be
// such (the light inside the box).
std::vector<glm::vec3> shadow_volume(const gpu::GpuLight& light, glm::vec3 lo, glm::vec3 hi, const Bounds& visible) {
  const glm::vec3 centre = 0.5f * (lo + hi);
  std::vector<glm::vec3> hull;
  if (uint32_t(light.position.w) == gpu::kLightSun) {
    // The box swept along the light's direction until it has left
    // `visible`, grown by the cone on the way: at a point p the test grows
    // it by tan * (|p - centre| + half), and a point swept t along lies
    // within t + half + sqrt(3) * growth of the centre, so the growth is
    // at most tan * (t + 2 half) / (1 - sqrt(3) tan), and never more than
    // at the visible point farthest from the box. Growing linearly, the
    // swept boxes lie in the hull of the first and the last.
    const glm::vec3 along = glm::normalize(glm::vec3(light.direction));
    const float tan = light.direction.w, half = glm::length(hi - centre);
    const float widest = tan * (farthest_corner(visible, centre) + half);
    auto growth = [&](float t) {
      const float shrink = 1.0f - std::sqrt(3.0f) * tan;
      return shrink > 0.0f ? std::min(widest, tan * (t + 2.0f * half) / shrink) : widest;
    };
    // (how far a box grown by g sweeps before it has left `visible` on an
    // axis it heads along; from the widest growth down, each length bounds
    // the growth on the way, which bounds the length again)
    auto sweep = [&](float g) {
      float length = std::numeric_limits<float>::max();
      for (int k = 0; k < 3; ++k) {
        if (along[k] < 0.0f) length = std::min(length, (visible.lo[k] - (hi[k] + g)) / along[k]);
        if (along[k] > 0.0f) length = std::min(length, (visible.hi[k] - (lo[k] - g)) / along[k]);
      }
      return std::max(length, 0.0f);
    };
    float length = sweep(widest);
    for (int i = 0; i < 4 && length < std::numeric_limits<float>::max(); ++i) length = sweep(growth(length));
    if (!(length < std::numeric_limits<float>::max())) return {};  // (never leaves: anywhere)
    const float first = growth(0.0f), last = growth(length);
    hull = corners(lo - first, hi + first);
    for (const glm::vec3& q : corners(lo - last, hi + last)) hull.push_back(q + length * along);
    return hull;
  }
  // From the light's point through the box, out to where its rays have left
  // `visible` (on an axis all of them head along; else at the distance of
  // its farthest corner).
  const glm::vec3 at(light.position);
  const glm::vec3 grown_lo = lo - light.direction.w, grown_hi = hi + light.direction.w;
  const float nearest = glm::length(glm::max(glm::max(grown_lo - at, at - grown_hi), 0.0f));
  if (nearest <= 0.0f) return {};
  float scale = farthest_corner(visible, at) / nearest;  // (in units of each ray to the box)
  for (int k = 0; k < 3; ++k) {
    const float low = grown_lo[k] - at[k], high = grown_hi[k] - at[k];  // (the rays' span on this axis)
    if (high < 0.0f) scale = std::min(scale, std::max(at[k] - visible.lo[k], 0.0f) / -high);
    if (low > 0.0f) scale = std::min(scale, std::max(visible.hi[k] - at[k], 0.0f) / low);
  }
  scale = std::max(scale, 1.0f);
  hull = corners(grown_lo, grown_hi);
  for (int k = 0; k < 8; ++k) hull.push_back(at + scale * (hull[k] - at));
  return hull;
}

}  // namespace

PixelRect change_on_screen(const gpu::FrameData& frame, const std::vector<gpu::GpuLight>& lights,
                           const Bounds& visible, glm::ivec2 size, float jitter_reach) {
  const glm::mat4& world_to_clip = frame.steady_world_to_clip;
  PixelRect region;
  if (frame.moved_lo.w != 0.0f)
    region = region.united(project_hull(world_to_clip, size, corners(frame.moved_lo, frame.moved_hi)));
  // The tests of contact and of light paths are of visible surface points:
  // their volumes end at `visible` (the rectangle of a volume's box cut by
  // it, within that of the volume).
  auto seen_part = [&](const std::vector<glm::vec3>& volume) {
    Bounds box{volume.front(), volume.front()};
    for (const glm::vec3& p : volume) box = {glm::min(box.lo, p), glm::max(box.hi, p)};
    const Bounds cut{glm::max(box.lo, visible.lo), glm::min(box.hi, visible.hi)};
    if (cut.is_empty()) return PixelRect{};
    return project_hull(world_to_clip, size, volume).intersected(project_hull(world_to_clip, size, corners(cut.lo, cut.hi)));
  };
  if (frame.changed_lo.w != 0.0f && !visible.is_empty()) {
    const glm::vec3 lo(frame.changed_lo), hi(frame.changed_hi);
    const float contact = gpu::kContactReach * glm::distance(lo, hi);
    region = region.united(seen_part(corners(lo - contact, hi + contact)));
    for (const gpu::GpuLight& light : lights) {
      const std::vector<glm::vec3> volume = shadow_volume(light, lo, hi, visible);
      if (volume.empty()) return PixelRect::whole(size);
      region = region.united(seen_part(volume));
    }
  }
  // The margin: a sample sees a point up to the jitter's reach from its
  // pixel's centre, both in history's frames and in this one; the test of a
  // silhouette's moved front grows the moved box by jitter_reach + 2 pixels;
  // and a pixel's history is read from the texels right of and below it too.
  const int reach = int(std::ceil(jitter_reach));
  return region.grown(2 * reach + 4, size);
}

}  // namespace rtsdf
