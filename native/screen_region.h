#pragma once
// Where on screen a change in the scene can show, found on the CPU before a
// frame is drawn: the temporal keep pass (shaders/temporal_keep.comp) and the
// G-buffer of a playback step run over that region alone, and the pixels
// outside it take history as it was (a plane copy). The tests here mirror the
// keep pass's own (shaders/temporal_history.glsl.h), each as a world volume
// projected to a rectangle that holds it: a pixel they would not keep lies
// inside, so drawing less changes no pixel's colour.
#include <glm/glm.hpp>
#include <vector>

#include "scene.h"
#include "shaders/shared.h"

namespace rtsdf {

// Pixels x in [lo.x, hi.x), y in [lo.y, hi.y); none when hi <= lo on an axis.
struct PixelRect {
  glm::ivec2 lo{0};
  glm::ivec2 hi{0};

  static PixelRect whole(glm::ivec2 size) { return {glm::ivec2(0), size}; }
  bool is_empty() const { return hi.x <= lo.x || hi.y <= lo.y; }
  glm::ivec2 size() const { return is_empty() ? glm::ivec2(0) : hi - lo; }
  // The smallest rectangle holding both.
  PixelRect united(const PixelRect& other) const;
  // The rectangle both hold.
  PixelRect intersected(const PixelRect& other) const;
  // Grown by `pixels` on every side, within an image of `size`.
  PixelRect grown(int pixels, glm::ivec2 size) const;
  bool operator==(const PixelRect& other) const {
    return (is_empty() && other.is_empty()) || (lo == other.lo && hi == other.hi);
  }
};

// The pixels (of an image of `size`) whose centres may see a point of the
// convex hull of `points`: the rectangle of their projections, grown by a
// pixel for the rounding. The whole image where a point lies at or behind
// the camera's plane (its hull may then reach round any side of the screen).
PixelRect project_hull(const glm::mat4& world_to_clip, glm::ivec2 size, const std::vector<glm::vec3>& points);

// The region of a frame's change (frame.changed_*, frame.moved_*, as the
// keep pass reads them) where the keep pass may find a pixel that is not
// settled whatever its new sample:
// - what moved, where its surfaces are now and were (a pixel's motion, an
//   uncovered background, a silhouette whose history held it);
// - surfaces in contact with the changed casters (within kContactReach of
//   their box's diagonal), within `visible`;
// - each light's shadow volume of the changed casters: the points whose path
//   to the light crosses their box (grown by the light's cone), cut where it
//   leaves `visible` (the world bounds of everything the camera may see:
//   no surface lies beyond them).
// Grown by the jitter's reach (`jitter_reach` pixels: a sample sees a point
// that far from its pixel's centre) and the few pixels the keep pass's
// tests look around. Empty where nothing changed.
PixelRect change_on_screen(const gpu::FrameData& frame, const std::vector<gpu::GpuLight>& lights,
                           const Bounds& visible, glm::ivec2 size, float jitter_reach);

}  // namespace rtsdf
