#pragma once
// Where on screen a change in the scene can show, found on the CPU before a
// frame is drawn: the temporal keep pass (shaders/temporal_keep.comp) of a
// playback step runs over those tiles alone (the G-buffer over a rectangle
// around them), and the pixels outside them take history as it was (a plane
// copy). The tests here mirror the keep pass's own
// (shaders/temporal_history.glsl.h), each as a convex world volume whose
// projected outline's tiles hold it: a pixel they would not keep lies
// inside, so drawing less changes no pixel's colour.
#include <glm/glm.hpp>
#include <algorithm>
#include <cstdint>
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
  // The rectangle both hold.
  PixelRect intersected(const PixelRect& other) const;
  // Grown by `pixels` on every side, within an image of `size`.
  PixelRect grown(int pixels, glm::ivec2 size) const;
  bool operator==(const PixelRect& other) const {
    return (is_empty() && other.is_empty()) || (lo == other.lo && hi == other.hi);
  }
};

// A set of tiles of an image (kTemporalTile pixels square, the keep pass's
// work groups): the shape of a change on screen, which a rectangle holding
// it may exceed several times over (a slanted shadow volume, a box and its
// shadow beside it).
class TileMask {
 public:
  TileMask() = default;
  explicit TileMask(glm::ivec2 image_size);
  static TileMask whole(glm::ivec2 image_size);

  glm::ivec2 image_size() const { return image_size_; }
  glm::ivec2 tiles() const { return tiles_; }
  bool is_empty() const { return marked_ == 0; }
  bool holds_tile(glm::ivec2 tile) const { return marked_ > 0 && bits_[index(tile)] != 0; }
  bool holds(glm::ivec2 pixel) const;
  // The share of the image's tiles marked.
  double share() const;
  // The smallest rectangle of whole tiles (within the image) holding them.
  PixelRect bounds() const;
  // Marked tiles as indices x + tiles().x * y, row by row.
  std::vector<uint32_t> indices() const;
  // The image outside them, as rectangles (runs of unmarked tiles along rows,
  // within the image).
  std::vector<PixelRect> outside() const;

  void mark(glm::ivec2 tile);
  // Every tile holding a pixel of `rect`.
  void add(const PixelRect& rect);
  void add(const TileMask& other);
  // The tiles both hold.
  TileMask intersected(const TileMask& other) const;
  // Every tile that a point of the convex polygon `hull` (pixel coordinates,
  // pixel i spanning [i, i + 1)), grown by `margin` pixels, reaches, within
  // `within` grown by as much.
  void add_convex(const std::vector<glm::vec2>& hull, float margin, const PixelRect& within);
  // Each marked tile's rectangle from across(x) and down(y), the tile ranges
  // (first, last) a marked tile in column x or row y spreads to.
  template <typename Across, typename Down>
  TileMask spread(Across across, Down down) const;

 private:
  size_t index(glm::ivec2 tile) const { return size_t(tile.x) + size_t(tiles_.x) * size_t(tile.y); }
  glm::ivec2 image_size_{0};
  glm::ivec2 tiles_{0};
  std::vector<uint8_t> bits_;
  size_t marked_ = 0;
};

template <typename Across, typename Down>
TileMask TileMask::spread(Across across, Down down) const {
  // (separable: a rectangle of ranges per tile is the rows' spread, then the columns')
  TileMask rows(image_size_), out(image_size_);
  for (int y = 0; y < tiles_.y; ++y)
    for (int x = 0; x < tiles_.x; ++x)
      if (holds_tile({x, y})) {
        const glm::ivec2 range = across(x);
        for (int to = std::max(range.x, 0); to <= std::min(range.y, tiles_.x - 1); ++to) rows.mark({to, y});
      }
  for (int y = 0; y < tiles_.y; ++y)
    for (int x = 0; x < tiles_.x; ++x)
      if (rows.holds_tile({x, y})) {
        const glm::ivec2 range = down(y);
        for (int to = std::max(range.x, 0); to <= std::min(range.y, tiles_.y - 1); ++to) out.mark({x, to});
      }
  return out;
}

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
//   their box's diagonal);
// - each light's shadow volume of the changed casters: the points whose path
//   to the light crosses their box (grown by the light's cone), swept until
//   it leaves the boxes `seen`.
// Surfaces lie in the boxes `seen` (the world bounds of what the camera may
// see: each instance's, or one holding them all): the last two are of
// surface points, and take only their parts inside those boxes.
// Each volume is convex; its tiles are those its projected outline reaches,
// grown by the jitter's reach (`jitter_reach` pixels: a sample sees a point
// that far from its pixel's centre) and the few pixels the keep pass's
// tests look around. Empty where nothing changed.
TileMask change_on_screen(const gpu::FrameData& frame, const std::vector<gpu::GpuLight>& lights,
                          const std::vector<Bounds>& seen, glm::ivec2 size, float jitter_reach);

}  // namespace rtsdf
