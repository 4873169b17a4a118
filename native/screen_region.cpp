#include "screen_region.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rtsdf {

PixelRect PixelRect::intersected(const PixelRect& other) const {
  const PixelRect both{glm::max(lo, other.lo), glm::min(hi, other.hi)};
  return both.is_empty() ? PixelRect{} : both;
}

PixelRect PixelRect::grown(int pixels, glm::ivec2 size) const {
  if (is_empty()) return *this;
  return {glm::max(lo - pixels, glm::ivec2(0)), glm::min(hi + pixels, size)};
}

TileMask::TileMask(glm::ivec2 image_size)
    : image_size_(glm::max(image_size, glm::ivec2(0))),
      tiles_((image_size_ + int(gpu::kTemporalTile) - 1) / int(gpu::kTemporalTile)),
      bits_(size_t(tiles_.x) * size_t(tiles_.y), 0) {}

TileMask TileMask::whole(glm::ivec2 image_size) {
  TileMask mask(image_size);
  mask.add(PixelRect::whole(image_size));
  return mask;
}

bool TileMask::holds(glm::ivec2 pixel) const {
  if (glm::any(glm::lessThan(pixel, glm::ivec2(0))) || glm::any(glm::greaterThanEqual(pixel, image_size_))) return false;
  return holds_tile(pixel / int(gpu::kTemporalTile));
}

double TileMask::share() const { return bits_.empty() ? 0.0 : double(marked_) / double(bits_.size()); }

void TileMask::mark(glm::ivec2 tile) {
  uint8_t& bit = bits_[index(tile)];
  marked_ += bit == 0 ? 1 : 0;
  bit = 1;
}

PixelRect TileMask::bounds() const {
  glm::ivec2 lo(tiles_), hi(-1);
  for (int y = 0; y < tiles_.y; ++y)
    for (int x = 0; x < tiles_.x; ++x)
      if (holds_tile({x, y})) lo = glm::min(lo, glm::ivec2(x, y)), hi = glm::max(hi, glm::ivec2(x, y));
  if (hi.x < 0) return {};
  const int tile = int(gpu::kTemporalTile);
  return {lo * tile, glm::min((hi + 1) * tile, image_size_)};
}

std::vector<uint32_t> TileMask::indices() const {
  std::vector<uint32_t> marked;
  marked.reserve(marked_);
  for (size_t i = 0; i < bits_.size(); ++i)
    if (bits_[i]) marked.push_back(uint32_t(i));
  return marked;
}

std::vector<PixelRect> TileMask::outside() const {
  const int tile = int(gpu::kTemporalTile);
  std::vector<PixelRect> runs;
  for (int y = 0; y < tiles_.y; ++y)
    for (int x = 0; x < tiles_.x;) {
      if (holds_tile({x, y})) { ++x; continue; }
      const int first = x;
      while (x < tiles_.x && !holds_tile({x, y})) ++x;
      const PixelRect run{glm::ivec2(first, y) * tile, glm::min(glm::ivec2(x, y + 1) * tile, image_size_)};
      // (a run under one of the row above, the same columns: one rectangle)
      if (!runs.empty() && runs.back().lo.x == run.lo.x && runs.back().hi.x == run.hi.x && runs.back().hi.y == run.lo.y)
        runs.back().hi.y = run.hi.y;
      else
        runs.push_back(run);
    }
  return runs;
}

void TileMask::add(const PixelRect& rect) {
  const PixelRect cut = rect.intersected(PixelRect::whole(image_size_));
  if (cut.is_empty()) return;
  const int tile = int(gpu::kTemporalTile);
  for (int y = cut.lo.y / tile; y <= (cut.hi.y - 1) / tile; ++y)
    for (int x = cut.lo.x / tile; x <= (cut.hi.x - 1) / tile; ++x) mark({x, y});
}

TileMask TileMask::intersected(const TileMask& other) const {
  if (other.tiles_ != tiles_) throw std::invalid_argument("TileMask: the masks are of images of other sizes");
  TileMask both(image_size_);
  for (size_t i = 0; i < bits_.size(); ++i) both.bits_[i] = bits_[i] & other.bits_[i];
  both.marked_ = size_t(std::count(both.bits_.begin(), both.bits_.end(), uint8_t(1)));
  return both;
}

void TileMask::add(const TileMask& other) {
  if (other.tiles_ != tiles_) throw std::invalid_argument("TileMask: the masks are of images of other sizes");
  for (size_t i = 0; i < bits_.size(); ++i) bits_[i] |= other.bits_[i];
  marked_ = size_t(std::count(bits_.begin(), bits_.end(), uint8_t(1)));
}

void TileMask::add_convex(const std::vector<glm::vec2>& hull, float margin, const PixelRect& within) {
  if (hull.empty()) return;
  // The axes that may part a tile from the polygon: the tiles' own, and
  // each edge's normal (the separating axis theorem, for convex shapes),
  // with the polygon's extent along each.
  struct Axis {
    glm::vec2 direction;
    float lo, hi;
  };
  std::vector<Axis> axes;
  for (size_t i = 0; i < hull.size() && hull.size() > 1; ++i) {
    const glm::vec2 edge = hull[(i + 1) % hull.size()] - hull[i];
    if (edge == glm::vec2(0.0f)) continue;
    Axis axis{glm::vec2(-edge.y, edge.x), std::numeric_limits<float>::max(), std::numeric_limits<float>::lowest()};
    for (const glm::vec2& p : hull) axis.lo = std::min(axis.lo, glm::dot(axis.direction, p)), axis.hi = std::max(axis.hi, glm::dot(axis.direction, p));
    axes.push_back(axis);
  }
  glm::vec2 lo = hull.front(), hi = hull.front();
  for (const glm::vec2& p : hull) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const int tile = int(gpu::kTemporalTile);
  PixelRect span{glm::ivec2(glm::floor(lo - margin)), glm::ivec2(glm::floor(hi + margin)) + 1};
  span = span.intersected(within.grown(int(std::ceil(margin)), image_size_));
  if (span.is_empty()) return;
  const glm::vec2 half(0.5f * float(tile) + margin);
  for (int y = span.lo.y / tile; y <= (span.hi.y - 1) / tile; ++y)
    for (int x = span.lo.x / tile; x <= (span.hi.x - 1) / tile; ++x) {
      const glm::vec2 centre = (glm::vec2(x, y) + 0.5f) * float(tile);
      const bool parted = std::any_of(axes.begin(), axes.end(), [&](const Axis& axis) {
        const float at = glm::dot(axis.direction, centre);
        const float reach = half.x * std::abs(axis.direction.x) + half.y * std::abs(axis.direction.y);
        return at + reach < axis.lo || at - reach > axis.hi;
      });
      if (!parted) mark({x, y});  // (the tiles' own axes part nothing within `span`)
    }
}

namespace {

// The pixel coordinates of p (pixel i spanning [i, i + 1)); false at or
// behind the camera's plane, where a point projects nowhere useful (its
// hull's edges towards it cross the screen's sides).
bool to_pixel(const glm::mat4& world_to_clip, glm::ivec2 size, glm::vec3 p, glm::vec2& pixel) {
  const glm::vec4 clip = world_to_clip * glm::vec4(p, 1.0f);
  if (!(clip.w > 1e-6f * std::max(std::abs(clip.x), std::abs(clip.y)) && clip.w > 0.0f)) return false;
  pixel = (glm::vec2(clip) / clip.w + 1.0f) * 0.5f * glm::vec2(size);
  return true;
}

// Projections of `points` to pixel coordinates; false where a point lies
// at or behind the camera's plane or too far out to place.
bool project_points(const glm::mat4& world_to_clip, glm::ivec2 size, const std::vector<glm::vec3>& points,
                    std::vector<glm::vec2>& pixels) {
  pixels.clear();
  glm::vec2 pixel;
  for (const glm::vec3& p : points) {
    if (!to_pixel(world_to_clip, size, p, pixel) || !(std::abs(pixel.x) < 1e6f && std::abs(pixel.y) < 1e6f))
      return false;
    pixels.push_back(pixel);
  }
  return true;
}

// The convex hull of `points` in order round it (Andrew's monotone chain).
std::vector<glm::vec2> convex_hull(std::vector<glm::vec2> points) {
  std::sort(points.begin(), points.end(), [](glm::vec2 a, glm::vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  auto turn = [](glm::vec2 o, glm::vec2 a, glm::vec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); };
  std::vector<glm::vec2> hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {  // (lower chain)
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], points[i]) <= 0.0f) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {  // (upper chain)
    while (k >= lower && turn(hull[k - 2], hull[k - 1], points[i]) <= 0.0f) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

}  // namespace

PixelRect project_hull(const glm::mat4& world_to_clip, glm::ivec2 size, const std::vector<glm::vec3>& points) {
  const PixelRect whole = PixelRect::whole(size);
  glm::vec2 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
  glm::vec2 pixel;
  for (const glm::vec3& p : points) {
    if (!to_pixel(world_to_clip, size, p, pixel) || !std::isfinite(pixel.x) || !std::isfinite(pixel.y)) return whole;
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

// The boxes the temporal passes test against (temporal_history.glsl.h): of
// the changed casters (changed_box: contact and light paths) or of every
// instance that moved (within_moved_box: a silhouette's moved front); each
// one's where they are few, else the one holding them all.
std::vector<Bounds> boxes_apart(uint32_t count, const glm::vec4* apart, glm::vec4 lo, glm::vec4 hi) {
  if (count == 0u) return {Bounds{glm::vec3(lo), glm::vec3(hi)}};
  std::vector<Bounds> boxes;
  for (uint32_t i = 0; i < count; ++i) boxes.push_back({glm::vec3(apart[2 * i]), glm::vec3(apart[2 * i + 1])});
  return boxes;
}

}  // namespace

TileMask change_on_screen(const gpu::FrameData& frame, const std::vector<gpu::GpuLight>& lights,
                          const std::vector<Bounds>& seen, glm::ivec2 size, float jitter_reach) {
  const glm::mat4& world_to_clip = frame.steady_world_to_clip;
  TileMask region(size);
  // The margin: a sample sees a point up to the jitter's reach from its
  // pixel's centre, both in history's frames and in this one; the test of a
  // silhouette's moved front grows the moved box by jitter_reach + 2 pixels;
  // a pixel's history is read from the texels right of and below it too;
  // and a pixel for the rounding.
  const float margin = float(2 * int(std::ceil(jitter_reach)) + 4 + 1);
  std::vector<glm::vec2> pixels;
  // The tiles of a convex volume within `within` (all of `within` where the
  // volume reaches behind the camera).
  auto volume_tiles = [&](const std::vector<glm::vec3>& volume, const PixelRect& within) {
    TileMask tiles(size);
    if (project_points(world_to_clip, size, volume, pixels))
      tiles.add_convex(convex_hull(pixels), margin, within);
    else
      tiles.add(within.grown(int(margin), size));
    return tiles;
  };
  const PixelRect whole = PixelRect::whole(size);
  if (frame.moved_lo.w != 0.0f)
    for (const Bounds& moved : boxes_apart(frame.boxes_apart.y, frame.moved_instances, frame.moved_lo, frame.moved_hi))
      region.add(volume_tiles(corners(moved.lo, moved.hi), whole));
  Bounds visible = Bounds::empty();
  for (const Bounds& box : seen)
    if (!box.is_empty()) visible = visible.is_empty() ? box : Bounds{glm::min(visible.lo, box.lo), glm::max(visible.hi, box.hi)};
  if (frame.changed_lo.w == 0.0f || visible.is_empty()) return region;
  // The tests of contact and of light paths are of visible surface points,
  // each inside the box of what it is on: a volume's tiles are those of its
  // parts inside those boxes (each a box, the volume's box cut by one;
  // within the volume's own outline). Seen from above, a box standing on a
  // ground reaches across much of the ground behind it on screen, but
  // meets the ground's own box only at its foot.
  auto add_seen_parts = [&](const std::vector<glm::vec3>& volume) {
    Bounds box{volume.front(), volume.front()};
    for (const glm::vec3& p : volume) box = {glm::min(box.lo, p), glm::max(box.hi, p)};
    TileMask parts(size);
    for (const Bounds& surfaces : seen) {
      const Bounds cut{glm::max(box.lo, surfaces.lo), glm::min(box.hi, surfaces.hi)};
      if (!surfaces.is_empty() && !cut.is_empty()) parts.add(volume_tiles(corners(cut.lo, cut.hi), whole));
    }
    if (parts.is_empty()) return;
    region.add(parts.intersected(volume_tiles(volume, parts.bounds())));
  };
  for (const Bounds& changed : boxes_apart(frame.boxes_apart.x, frame.changed_casters, frame.changed_lo, frame.changed_hi)) {
    const glm::vec3 lo = changed.lo, hi = changed.hi;
    const float contact = gpu::kContactReach * glm::distance(lo, hi);
    add_seen_parts(corners(lo - contact, hi + contact));
    for (const gpu::GpuLight& light : lights) {
      const std::vector<glm::vec3> volume = shadow_volume(light, lo, hi, visible);
      if (volume.empty()) return TileMask::whole(size);
      add_seen_parts(volume);
    }
  }
  return region;
}

}  // namespace rtsdf
