// History from before a change, as this frame's pixels find it: where each
// pixel's surface point was (the G-buffer's motion), what history holds
// there, whether it shows the same surface, and whether what moved can have
// changed it. Shared by the temporal passes: the keep pass
// (temporal_keep.comp) keeps the pixels whose history stands whatever this
// frame's sample, before any shading, and the resolve
// (temporal_resolve.comp) decides the rest with the sample.
// Needs: the TemporalPush `pc`, g_position, g_motion, g_normal, g_albedo,
// history_color, history_passes, resolved_color, resolved_passes and
// resolved_moments (History handed on),
// the Frame buffer `frame`, the lights and the tile lists `tile_words`
// (kept_tiles.glsl.h).
#include "ray_box.glsl.h"
#include "kept_tiles.glsl.h"

// The path from p to a light (a cone towards its disk): its axis to_light,
// which reaches the light at 1 (a sun's: never).
struct LightCone {
  vec3 to_light;
  float t_max;
  float radius;  // a sun's: the tangent of its angular radius; else the light's radius
  bool sun;
};

LightCone light_cone(vec3 p, GpuLight light) {
  bool sun = uint(light.position.w) == kLightSun;
  return LightCone(sun ? -light.direction.xyz : light.position.xyz - p, sun ? 1e30 : 1.0, light.direction.w, sun);
}

// Where the cone from p meets the box lo, hi: the stretch of its axis in
// the box grown by the cone's radius there (x > y: it does not).
vec2 cone_span_in_box(vec3 p, LightCone cone, vec3 lo, vec3 hi) {
  vec3 centre = 0.5 * (lo + hi);
  float grow = cone.sun ? cone.radius * (distance(p, centre) + length(hi - centre)) : cone.radius;
  vec2 span = ray_box_span(p, safe_inverse(cone.to_light), lo - grow, hi + grow);
  return vec2(max(span.x, 0.0), min(span.y, cone.t_max));
}

// The boxes of the casters that moved or deformed: each one's
// (frame.changed_casters), or where they are many one holding them all.
uint changed_box_count() { return frame.changed_lo.w == 0.0 ? 0u : max(frame.boxes_apart.x, 1u); }

void changed_box(uint i, out vec3 lo, out vec3 hi) {
  bool each = frame.boxes_apart.x > 0u;
  lo = each ? frame.changed_casters[2u * i].xyz : frame.changed_lo.xyz;
  hi = each ? frame.changed_casters[2u * i + 1u].xyz : frame.changed_hi.xyz;
}

// Whether the paths from p to light l cross the box of a caster that moved.
bool light_path_crosses_change(vec3 p, int l) {
  LightCone cone = light_cone(p, lights[l]);
  for (uint i = 0u; i < changed_box_count(); ++i) {
    vec3 lo, hi;
    changed_box(i, lo, hi);
    vec2 span = cone_span_in_box(p, cone, lo, hi);
    if (span.x <= span.y) return true;
  }
  return false;
}

// Whether p is within `distance` of the box lo, hi (lo.w = 0: an empty box).
bool within_box(vec3 p, vec4 lo, vec4 hi, float distance) {
  if (lo.w == 0.0) return false;
  vec3 outside = max(max(lo.xyz - p, p - hi.xyz), 0.0);
  return length(outside) <= distance;
}

// Whether p lies within `distance` of the box of an instance that moved or
// deformed (frame.moved_instances; where they are many, the one holding them all).
bool within_moved_box(vec3 p, float distance) {
  if (frame.moved_lo.w == 0.0) return false;
  if (frame.boxes_apart.y == 0u) return within_box(p, frame.moved_lo, frame.moved_hi, distance);
  for (uint i = 0u; i < frame.boxes_apart.y; ++i)
    if (within_box(p, frame.moved_instances[2u * i], frame.moved_instances[2u * i + 1u], distance)) return true;
  return false;
}

// Where a still pixel is in contact with what moved: within this share of
// a changed box's size (its diagonal) of that box. There the sky it sees
// changes fast with the motion (a contact shadow), and it is sampled anew as
// a moving pixel is (the resolve keeps its history where this frame's
// neighbourhood holds it). Beyond it, the sky's change follows the moved object's
// share of the hemisphere, which falls with the square of the distance.
// Taking a new sample there each frame (up to a whole box size out) made
// flicker: the new samples' noise showed more than the sky's change, and the
// error against Cycles was the same within 3% on six bench scenes
// (docs/benchmarks.md). kContactReach (shared.h) is that share; the
// renderer bounds the keep pass's region by it too (native/screen_region.h).

bool in_contact_with_change(vec3 p) {
  for (uint i = 0u; i < changed_box_count(); ++i) {
    vec3 lo, hi;
    changed_box(i, lo, hi);
    if (within_box(p, vec4(lo, 1.0), vec4(hi, 1.0), kContactReach * length(hi - lo))) return true;
  }
  return false;
}

// The world width of a pixel at p (from the projection's first row: the
// view's x axis, scaled; a lens shift's share along the view left out).
float pixel_width_at(vec3 p) {
  mat4 m = frame.steady_world_to_clip;
  vec3 row = vec3(m[0][0], m[1][0], m[2][0]), forward = frame.camera_forward.xyz;
  float scale = length(row - dot(row, forward) * forward);
  return 2.0 * abs((m * vec4(p, 1.0)).w) / (float(pc.image_size.x) * max(scale, 1e-20));
}

// Whether a history texel whose passes are `range` saw depth `depth`: within
// the range of depths its samples saw (passes x to w), give or take
// depth_tolerance of it.
bool saw_depth(vec4 range, float depth) {
  return depth >= range.x * (1.0 - pc.depth_tolerance) && depth <= range.w * (1.0 + pc.depth_tolerance);
}

bool same_depth(ivec2 q, float depth) {
  return saw_depth(imageLoad(history_passes, clamp(q, ivec2(0), pc.image_size - 1)), depth);
}

// Whether a texel within jitter_reach pixels of q saw depth `depth`. The
// sub-pixel jitter (up to jitter_reach pixels, the same for every pixel of a
// frame) moves a silhouette by as much from frame to frame, so this frame's
// sample may see a surface that q's samples never did though a neighbour's
// did. Such history is uncertain (it may as well be what just moved away):
// it counts as few samples.
bool near_depth(ivec2 q, float depth) {
  int reach = int(pc.jitter_reach);
  for (int dy = -reach; dy <= reach; ++dy)
    for (int dx = -reach; dx <= reach; ++dx)
      if (same_depth(q + ivec2(dx, dy), depth)) return true;
  return false;
}

struct History {
  bool disoccluded;      // history there shows other surfaces only (or the point was behind the last camera)
  vec4 color;            // history's Combined, read bilinearly where the point was
  float shadow;          // ... its Shadow pass
  float samples;         // the samples it stands for (few where matched only within the jitter's reach)
  float full_samples;    // the least samples of the texels read, matched or not
  float nearest;         // the nearest and farthest depths its samples saw
  float farthest;
  float previous_depth;  // the point's depth from the last camera (the G-buffer motion's z)
  vec3 on_ray;           // a point on this pixel's camera ray (the background's: on the near plane)
  bool front_moved;      // its nearest surface was what moved: it mixes in an object that has left
  bool stays;            // where it was on screen (a surface that did not move, under a still camera)
  bool still;            // full history where it was on screen, nothing moved in front of it, same lighting
  bool away;             // the background, or beyond contact with the changed box (in_contact_with_change)
  bool shadow_may_move;  // a path to a light crosses the box of the casters that moved
  // History where the shadow now on this point was (follow_shadow): its
  // Combined (with this pixel's albedo), Shadow pass and samples (0: none found).
  vec3 followed_color;
  float followed_shadow;
  float followed_samples;
  bool followed_alone;  // ... and the light path meets no caster that stayed (what moved alone shadows it)
  bool shadow_carried;  // a moving surface whose shadow moved with it (moving_along_with, path_moved_with)
  // History's texel at this pixel as it is, read once: Combined, passes and
  // second moments (whose w holds the instances its samples saw: see
  // kHistoryBits). A pixel the keep pass keeps takes them (settled), each
  // image read again costing it about a millisecond a site on lavapipe.
  vec4 own_color;
  vec4 own_passes;
  vec4 own_moments;
};

// The first of the casters that moved (frame.shadow_movers) that the cone
// from p meets; -1: none. `span`: where its axis is in that one's box.
int first_mover_on_path(vec3 p, LightCone cone, out vec2 span) {
  int first = -1;
  for (uint i = 0u; i < frame.shadow_counts.x; ++i) {
    vec2 s = cone_span_in_box(p, cone, frame.shadow_movers[kShadowMoverWords * i].xyz,
                              frame.shadow_movers[kShadowMoverWords * i + 1u].xyz);
    if (s.x <= s.y && (first < 0 || s.x < span.x)) first = int(i), span = s;
  }
  return first;
}

// Whether the cone from p meets a caster that stayed (frame.still_casters).
bool path_meets_still_caster(vec3 p, LightCone cone) {
  for (uint i = 0u; i < frame.shadow_counts.y; ++i) {
    vec2 s = cone_span_in_box(p, cone, frame.still_casters[2u * i].xyz, frame.still_casters[2u * i + 1u].xyz);
    if (s.x <= s.y) return true;
  }
  return false;
}

// Whether mover i moved along alone: no turn or scale in its motion (its
// world_to_previous_world's rows), and its mesh kept its shape.
bool moved_along(uint i) {
  uint words = kShadowMoverWords * i;
  if (frame.shadow_movers[words].w != 0.0) return false;  // (deformed)
  for (uint row = 0u; row < 3u; ++row) {
    vec3 unit = vec3(row == 0u ? 1.0 : 0.0, row == 1u ? 1.0 : 0.0, row == 2u ? 1.0 : 0.0);
    if (any(greaterThan(abs(frame.shadow_movers[words + 2u + row].xyz - unit), vec3(1e-4)))) return false;
  }
  return true;
}

// Whether movers i and j moved by the same motion.
bool moved_together(uint i, uint j) {
  for (uint row = 2u; row < kShadowMoverWords; ++row)
    if (any(greaterThan(abs(frame.shadow_movers[kShadowMoverWords * i + row] -
                            frame.shadow_movers[kShadowMoverWords * j + row]), vec4(1e-4))))
      return false;
  return true;
}

// The shadow on a point p of a moving surface moved with it where p lies on
// a caster that only moved along (moving_along_with: its box holds p), and
// every path from p to a light whose paths cross the changed box goes to a
// sun and meets only casters that moved along with it (path_moved_with).
// A sun's light then reaches p past the same surfaces as before, so the
// shadow there (a moving bolt's threads shading each other) is history's,
// and where this frame's sample differs from it, that is the sample's
// noise: the resolve's moved-shadow test allows for it
// (temporal_resolve.comp). Tested as any moved shadow, the noise restarted
// such history at almost every step, and a moving caster's self-shadows
// were as speckled as one sample. A turn, a deformation, a light that is
// not a sun, or a caster on the path that did not move with p keeps the
// plain test.

// The first mover whose box holds p and that moved along (-1: none).
int moving_along_with(vec3 p) {
  for (uint i = 0u; i < frame.shadow_counts.x; ++i)
    if (all(greaterThanEqual(p, frame.shadow_movers[kShadowMoverWords * i].xyz)) &&
        all(lessThanEqual(p, frame.shadow_movers[kShadowMoverWords * i + 1u].xyz)) && moved_along(i))
      return int(i);
  return -1;
}

// Whether the path from p to light l goes to a sun and meets only casters
// that moved as mover `own` did.
bool path_moved_with(vec3 p, int l, uint own) {
  LightCone cone = light_cone(p, lights[l]);
  if (!cone.sun || path_meets_still_caster(p, cone)) return false;
  for (uint i = 0u; i < frame.shadow_counts.x; ++i) {
    vec2 span = cone_span_in_box(p, cone, frame.shadow_movers[kShadowMoverWords * i].xyz,
                                 frame.shadow_movers[kShadowMoverWords * i + 1u].xyz);
    if (span.x <= span.y && !moved_together(i, own)) return false;
  }
  return true;
}

// The Catmull-Rom weights of texels -1, 0, 1 and 2 along each axis, for a
// read at fraction f past texel 0 (they sum to 1 and reach past the four
// nearest, so a read of history moved step after step keeps its detail
// where a bilinear read blurs it).
vec2[4] catmull_rom_weights(vec2 f) {
  return vec2[4](f * (-0.5 + f * (1.0 - 0.5 * f)), 1.0 + f * f * (-2.5 + 1.5 * f), f * (0.5 + f * (2.0 - 1.5 * f)),
                 f * f * (-0.5 + 0.5 * f));
}

// Where a moved shadow's history is. A caster that moved rigidly carries its
// shadow with it: the light's path from p passes the caster at b, which was
// at b_before (its world_to_previous_world), and the shadow now at p was
// then where the light's path through b_before met p's surface. History
// there (its tangent plane at p, read where the last camera saw it, on the
// same surface) is this shadow's, with the samples it gathered: a moved
// shadow need not start over from one sample, as the receiver's own history
// (a shadow that has left) has it. b is the middle of the path's stretch in
// the caster's box: exact for a caster that only moved along (the shadow
// on a plane then moves by the same offset wherever b is), an estimate for
// one that turned, which the resolve's neighbourhood clip bounds. Only for
// a receiver where it was on screen, under the same lights, with one light's
// path past what moved (two lights' shadows move apart). followed_alone:
// neither path (from p, from where the shadow was) meets a caster that
// stayed, so what moved alone shadows both, and the resolve takes this
// history whatever its sample; else the sample decides (a still caster's
// shadow there would be read a move's length off).
// `crossing`: the one light whose paths cross the changed box (find_history
// finds it; -1 where none or several do).
void follow_shadow(ivec2 pixel, vec3 p, int crossing, inout History h) {
  h.followed_samples = 0.0;
  if (frame.shadow_counts.x == 0u || !h.stays || pc.same_lighting != 1u || crossing < 0) return;
  GpuLight light = lights[crossing];
  LightCone cone = light_cone(p, light);
  vec2 span;
  int mover = first_mover_on_path(p, cone, span);
  if (mover < 0) return;
  uint words = kShadowMoverWords * uint(mover);
  vec4 b = vec4(p + cone.to_light * (0.5 * (span.x + span.y)), 1.0);
  vec3 b_before = vec3(dot(frame.shadow_movers[words + 2u], b), dot(frame.shadow_movers[words + 3u], b),
                       dot(frame.shadow_movers[words + 4u], b));
  // The path from the light through b_before, onto p's tangent plane.
  vec3 n = imageLoad(g_normal, pixel).xyz, away = cone.sun ? light.direction.xyz : b_before - light.position.xyz;
  float along = dot(n, away);
  if (abs(along) < 1e-3 * length(away)) return;
  vec3 p_before = b_before + away * (dot(n, p - b_before) / along);
  vec4 clip = frame.previous_world_to_clip * vec4(p_before, 1.0);
  if (clip.w <= 0.0) return;
  float depth_before = dot(p_before - frame.previous_camera_position.xyz, frame.previous_camera_forward.xyz);
  // Read as light (colour over albedo) from texels on the same surface that
  // saw that depth: the albedo is this pixel's, not the one the shadow fell
  // on. Through a Catmull-Rom filter over 4x4 texels where all are on it,
  // kept within the four nearest (else bilinearly, over those of the four
  // that are): a moving shadow is read again at each step, and a bilinear
  // read's blur, step after step, softened its edges.
  vec2 at = (clip.xy / clip.w * 0.5 + 0.5) * vec2(pc.image_size) - 0.5;
  ivec2 base = ivec2(floor(at));
  vec2 f = at - vec2(base);
  vec2 cubic[4] = catmull_rom_weights(f);
  vec4 smooth_sum = vec4(0.0), linear_sum = vec4(0.0);  // (light, shadow)
  vec4 lo = vec4(1e30), hi = vec4(-1e30);
  float samples = 1e30, weights = 0.0;
  bool whole = true;
  for (int k = 0; k < 16; ++k) {
    ivec2 offset = ivec2(k & 3, k >> 2) - 1, texel = clamp(base + offset, ivec2(0), pc.image_size - 1);
    bool inner = all(greaterThanEqual(offset, ivec2(0))) && all(lessThanEqual(offset, ivec2(1)));
    vec4 before = imageLoad(history_passes, texel);
    vec3 albedo = imageLoad(g_albedo, texel).rgb;
    bool on_surface = texel == base + offset && saw_depth(before, depth_before) &&
                      all(greaterThanEqual(albedo, vec3(1e-3))) && abs(dot(imageLoad(g_normal, texel).xyz, n)) >= 0.9;
    whole = whole && on_surface;
    if (!on_surface) continue;
    vec4 value = vec4(imageLoad(history_color, texel).rgb / albedo, before.y);
    smooth_sum += cubic[offset.x + 1].x * cubic[offset.y + 1].y * value;
    if (!inner) continue;
    vec2 bilinear = mix(1.0 - f, f, vec2(offset));
    float w = bilinear.x * bilinear.y;
    linear_sum += w * value;
    weights += w;
    lo = min(lo, value), hi = max(hi, value);
    samples = min(samples, before.z);
    // (a texel that saw a nearer surface too, a silhouette's, stands for few
    // samples, as the pixel's own history matched within the jitter's reach
    // does; nearer by 5 tolerances, beyond a grazing surface's spread of
    // depths within a pixel)
    if (before.x < depth_before * (1.0 - 5.0 * pc.depth_tolerance)) samples = min(samples, kNearbyHistorySamples);
  }
  vec3 albedo = imageLoad(g_albedo, pixel).rgb;
  if (weights < 0.5 || any(lessThan(albedo, vec3(1e-3)))) return;  // (half of it elsewhere: not this surface's)
  vec4 value = whole ? clamp(smooth_sum, lo, hi) : linear_sum / weights;
  h.followed_color = value.rgb * albedo;
  h.followed_shadow = value.a;
  h.followed_samples = min(samples, float(pc.history_samples));
  // (from both ends: where the shadow was, a still caster's may have lain too)
  h.followed_alone = !path_meets_still_caster(p, cone) && !path_meets_still_caster(p_before, light_cone(p_before, light));
}

// History that moved on screen, read through a Catmull-Rom filter over the
// 4x4 texels around where it was, where all of them saw that depth (the
// filter mixes no other surface) and stand for samples gathered, not
// restarted, and kept within the range of the four nearest. A moving
// surface's history is read again at each step, and a bilinear read's
// blur, step after step, washed out detail a few pixels wide (the engine
// sample's fins). History restarted a step ago (a moved shadow's, capped at
// moved_shadow_samples, then one sample more) is one or two noisy samples,
// and the filter's sharpening carried that noise on: read so everywhere,
// the Final row's playback error fell on the engine (0.0585 -> 0.0536) and
// rose on bolts (0.0381 -> 0.0404) and ivy (0.0537 -> 0.0552); from
// kNearbyHistorySamples up, the engine 0.0541, the CAD part 0.0369 -> 0.0350,
// and no bench scene worse (docs/benchmarks.md).
void sharpen_moved_history(ivec2 base, vec2 f, float depth, inout History h) {
  if (all(lessThan(abs(f), vec2(1e-3)))) return;  // (where it was exactly: nothing to filter)
  vec2 cubic[4] = catmull_rom_weights(f);
  vec4 sum = vec4(0.0), lo = vec4(1e30), hi = vec4(-1e30);
  for (int k = 0; k < 16; ++k) {
    ivec2 offset = ivec2(k & 3, k >> 2) - 1, texel = base + offset;
    if (any(lessThan(texel, ivec2(0))) || any(greaterThanEqual(texel, pc.image_size))) return;
    vec4 before = imageLoad(history_passes, texel);
    if (!saw_depth(before, depth) || before.z < kNearbyHistorySamples) return;
    vec4 value = vec4(imageLoad(history_color, texel).rgb, before.y);
    sum += cubic[offset.x + 1].x * cubic[offset.y + 1].y * value;
    if (all(greaterThanEqual(offset, ivec2(0))) && all(lessThanEqual(offset, ivec2(1))))
      lo = min(lo, value), hi = max(hi, value);
  }
  vec4 value = clamp(sum, lo, hi);
  h.color.rgb = value.rgb;
  h.shadow = value.a;
}

// The depth this frame sees at a G-buffer `position` (as the shading's Depth
// pass has it: kNothingHitDepth where no surface is).
float seen_depth(vec4 position) {
  return position.w > 0.0 ? dot(position.xyz - frame.camera_position.xyz, frame.camera_forward.xyz) : kNothingHitDepth;
}

// The history of `pixel` (its G-buffer position `position`).
History find_history(ivec2 pixel, vec4 position) {
  History h;
  h.disoccluded = true;
  h.color = vec4(0.0);
  h.shadow = 0.0;
  h.samples = 1e30;
  h.full_samples = 1e30;
  h.nearest = kNothingHitDepth;
  h.farthest = 0.0;
  h.front_moved = false;
  h.stays = false;
  h.still = false;
  h.away = true;
  h.shadow_may_move = false;
  h.followed_color = vec3(0.0);
  h.followed_shadow = 0.0;
  h.followed_samples = 0.0;
  h.followed_alone = false;
  h.shadow_carried = false;
  h.own_color = vec4(0.0);
  h.own_passes = vec4(0.0);
  h.own_moments = imageLoad(history_moments, pixel);
  vec4 motion = imageLoad(g_motion, pixel);
  h.previous_depth = motion.z;
  h.on_ray = position.xyz;
  bool background = position.w <= 0.0;
  if (background) {
    // The world behind everything moves with the camera alone: where this
    // pixel's ray met the far plane (with none, as cameras from Blender
    // have, the ray's direction: a homogeneous point at infinity), seen
    // from the last camera. Through the one matrix made in double
    // precision: a camera that stays puts the background exactly where it
    // was, and it settles (an inverse in single precision of a projection
    // without far plane put it anywhere, and the horizon flickered; the
    // inverse is made once, on the CPU, where each pixel's cost a tenth of
    // the pass on lavapipe).
    vec2 ndc = (vec2(pixel) + 0.5) / vec2(pc.image_size) * 2.0 - 1.0;
    vec4 near_point = frame.steady_clip_to_world * vec4(ndc, 0.0, 1.0);
    vec4 before = frame.steady_clip_to_previous_clip * vec4(ndc, 1.0, 1.0);
    if (abs(near_point.w) < 1e-20 || before.w <= 0.0) return h;
    h.on_ray = near_point.xyz / near_point.w;
    motion = vec4(before.xy / before.w - ndc, kNothingHitDepth, 1.0);
  }

  // A pixel beside the outline of a nearer surface (in its 3x3
  // neighbourhood) that moved otherwise reads history where that surface
  // was (the motion of the nearest depth around, as in Karis's temporal
  // supersampling): there history holds the outline anti-aliased over the
  // samples before, which the one new sample cannot; where the pixel's own
  // surface was, it held the object before it moved (or not yet), and was
  // dropped, so moving outlines were as jagged as one sample (their pixels
  // most of a playback frame's error beyond the still frame's on the bench
  // scenes). The resolve's clip to this frame's neighbourhood bounds what
  // such history brings. `front_change`: that surface's move in depth.
  float own_depth = seen_depth(position), front_depth = own_depth, front_change = 0.0;
  ivec2 front = pixel;
  for (int k = 0; k < 9; ++k) {
    ivec2 q = pixel + ivec2(k % 3, k / 3) - 1;
    if (k == 4 || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, pc.image_size))) continue;
    float d = seen_depth(imageLoad(g_position, q));
    if (d < front_depth * (1.0 - pc.depth_tolerance)) front = q, front_depth = d;
  }
  bool dilated = false;
  if (front != pixel) {
    vec4 front_motion = imageLoad(g_motion, front);
    if (front_motion.w > 0.0 && front_motion.xy != motion.xy) {
      front_change = front_depth - front_motion.z;
      motion = front_motion;
      dilated = true;
    }
  }

  // Where the surface point was: pixel centre + motion (in pixels), read
  // bilinearly (nothing where it was behind the last camera).
  vec2 at = vec2(pixel) + 0.5 + motion.xy * 0.5 * vec2(pc.image_size) - 0.5;
  ivec2 base = ivec2(floor(at));
  vec2 f = at - vec2(base);
  float weights = 0.0;
  for (int k = 0; k < 4 && motion.w > 0.0; ++k) {
    ivec2 corner = base + ivec2(k & 1, k >> 1);
    if (any(lessThan(corner, ivec2(0))) || any(greaterThanEqual(corner, pc.image_size))) continue;
    vec4 before = imageLoad(history_passes, corner);
    if (corner == pixel) h.own_passes = before;
    h.full_samples = min(h.full_samples, before.z);
    // (a texel of no weight, as three are where the point stayed on its
    // pixel, is not searched around: near_depth reads up to 9 texels)
    vec2 bilinear = mix(1.0 - f, f, vec2(k & 1, k >> 1));
    float w = bilinear.x * bilinear.y;
    if (w <= 0.0) continue;
    if (!saw_depth(before, motion.z)) {
      if (!near_depth(corner, motion.z)) continue;
      before.z = min(before.z, kNearbyHistorySamples);
    }
    vec4 color = imageLoad(history_color, corner);
    if (corner == pixel) h.own_color = color;
    h.color += w * color;
    h.shadow += w * before.y;
    h.samples = min(h.samples, before.z);
    h.nearest = min(h.nearest, before.x);
    h.farthest = max(h.farthest, before.w);
    weights += w;
  }
  h.disoccluded = weights < 1e-3;
  if (h.disoccluded) return h;
  h.stays = all(lessThan(abs(at - vec2(pixel)), vec2(1e-3)));  // (where it was on screen)
  h.color /= weights;
  h.shadow /= weights;
  if (weights > 0.999 && h.samples >= kNearbyHistorySamples) sharpen_moved_history(base, f, motion.z, h);

  // A silhouette's history holds the surfaces in front as well (its nearest
  // depth). Where that front surface was what moved, this pixel's history
  // mixes in an object that has left it: it is uncertain, and never settled.
  // (The same for the background: where an object moved off it, history
  // near its old outline still holds it.)
  if (h.nearest < kNothingHitDepth) {
    vec3 camera = frame.camera_position.xyz, forward = frame.camera_forward.xyz;
    vec3 ray = frame.camera_position.w > 0.5 ? forward : normalize(h.on_ray - camera);
    float depth = background ? kNothingHitDepth : dot(h.on_ray - camera, forward);
    vec3 history_front = h.on_ray + ray * ((h.nearest - dot(h.on_ray - camera, forward)) / max(dot(ray, forward), 1e-3));
    // (that front surface was seen within the jitter's reach of this pixel's
    // ray, read bilinearly: a moved object's lies in the box of what moved,
    // casting shadows or not, give or take that many pixels; a whole box's
    // size more took in the ground's far edge, and the horizon never settled)
    // Or, at a pixel whose surface stayed where it was, history saw an
    // instance that moved and the pixel now shows one that did not (their
    // bits: shared.h's kHistoryBits): that object lay closer in front of the
    // surface than depths can tell. IvyGen's stems, a centimetre off their
    // wall, passed for the wall, and after the ivy moved their image stayed
    // on it, settled for good.
    uint moved_bits = frame.shadow_counts.z;
    bool saw_mover = h.stays && (uint(h.own_moments.w) & moved_bits) != 0u &&
                     (surface_bits(pixel, position) & moved_bits) == 0u;
    // (read where a nearer surface beside it was: whether history's front is
    // nearer than that surface now; else whether it is nearer than this
    // surface, history's depths moved first as this surface moved in depth
    // since, as the resolve moves them: compared unmoved, the pixels of a
    // surface moving away from the camera by more than depth_tolerance a
    // step found history's nearest depth in front of them, and counted as
    // few samples at every step)
    float own_change = background ? 0.0 : depth - h.previous_depth;
    bool front_nearer = dilated ? h.nearest + front_change < front_depth * (1.0 - pc.depth_tolerance)
                                : h.nearest + own_change < depth * (1.0 - pc.depth_tolerance);
    h.front_moved = (front_nearer || saw_mover) &&
                    within_moved_box(history_front, (pc.jitter_reach + 2.0) * pixel_width_at(history_front));
  }
  int crossing = -1;  // (the light whose paths cross it, where one alone does)
  int own = h.stays || background || pc.same_lighting != 1u ? -1 : moving_along_with(position.xyz);
  h.shadow_carried = own >= 0;
  for (int l = 0; l < pc.light_count && !background; ++l)
    if (light_path_crosses_change(position.xyz, l)) {
      crossing = h.shadow_may_move ? -1 : l, h.shadow_may_move = true;
      h.shadow_carried = h.shadow_carried && path_moved_with(position.xyz, l, uint(own));
    }
  h.shadow_carried = h.shadow_carried && h.shadow_may_move;
  // Still: under the same lights and world, full history that stays on
  // screen where it was, with no moved object in front of it before (the
  // resolve leaves out, too, what lies in a moved shadow). A silhouette's
  // new sample may see a surface its history never did (the jitter goes on
  // to offsets the still frames did not take); away from what moved, that
  // is the jitter, not motion, so its full history counts here.
  h.still = pc.same_lighting == 1u && min(h.full_samples, float(pc.history_samples)) >= float(pc.history_samples) &&
            !h.front_moved && h.stays;
  h.away = background || !in_contact_with_change(position.xyz);
  if (h.shadow_may_move) follow_shadow(pixel, position.xyz, crossing, h);
  // History's depths as the resolve moves them (by this pixel's own move in
  // depth since, previous_depth; the background's by none): read where the
  // nearer surface was, they moved as it did. (A sky pixel's own motion in
  // the G-buffer is empty: taken as its move, it put history's depths 1e10
  // behind the camera, and beside a moving outline the sky settled on the
  // object's colour, a dot a step.)
  if (dilated) {
    float shift = front_change - (background ? 0.0 : own_depth - h.previous_depth);
    if (h.nearest < kNothingHitDepth) h.nearest += shift;
    if (h.farthest < kNothingHitDepth) h.farthest += shift;
  }
  return h;
}

// Settled whatever this frame's sample: still, beyond contact with what
// moved and out of any path past it to a light. Such a pixel
// keeps its converged value; a new jittered sample would only make it
// shimmer from frame to frame (what the still accumulation stops doing after
// its samples too).
bool settled_before_sample(History h) {
  return !h.disoccluded && h.still && h.away && !h.shadow_may_move;
}

// Whether history may stand for one sample or none: dropped, or on a
// surface that stays where it was, with a light path past what moved, where
// the resolve caps a moved shadow's history at moved_shadow_samples. (A
// bound: most such pixels keep their shadow.) Not on a moving surface: its
// history moves with it, and more rays there too (the engine sample's
// moving part) made a playback step's quad pass 1.7x as long for the same
// error of the frame shown. A moved shadow followed to where it was
// (follow_shadow) is marked too: where a still caster may shadow it, the
// resolve's choice of history goes by the sample, and more rays made it
// the better one (with the sample choosing everywhere, sphere_plane's
// playback frame at 4 exact rays was 1.14x the still frame's error, 1.53x
// without).
bool history_may_be_short(History h) { return h.disoccluded || (h.shadow_may_move && h.stays); }

// The keep pass hands each pixel it did not keep its History, in the
// resolved images (free until the resolve writes them), so that the resolve
// does not find it again: on lavapipe the search (four texels, their
// neighbours, the light paths) ran in every lane of a listed tile, and where
// few tiles were whole (a tree's canopy) the keep pass's search over
// every pixel was a cost added to one the resolve paid again. The point's
// depth from the last camera is the G-buffer motion's z, read again.
// The followed shadow's history (follow_shadow) goes in the resolved
// moments (Combined, Shadow pass) and its samples in the flags' word above
// kHistoryFollowedShift.
const uint kHistoryDisoccluded = 1u, kHistoryFrontMoved = 2u, kHistoryStill = 4u, kHistoryAway = 8u,
           kHistoryShadowMayMove = 16u, kHistoryFollowedAlone = 32u, kHistoryShadowCarried = 64u,
           kHistoryFollowedShift = 8u;

// A pixel's resolved accumulation, as a temporal pass decides it and then
// writes it, each image once: on lavapipe every image access in a shader's
// code costs its lanes, whichever branch they took.
struct Resolved {
  vec4 color;
  vec4 passes;
  vec4 moments;
};

// The History handed on, in the places of the resolved colour and passes (handed_history reads it).
Resolved history_handed_on(History h) {
  uint flags = (h.disoccluded ? kHistoryDisoccluded : 0u) | (h.front_moved ? kHistoryFrontMoved : 0u) |
               (h.still ? kHistoryStill : 0u) | (h.away ? kHistoryAway : 0u) |
               (h.shadow_may_move ? kHistoryShadowMayMove : 0u) | (h.followed_alone ? kHistoryFollowedAlone : 0u) |
               (h.shadow_carried ? kHistoryShadowCarried : 0u) |
               (uint(h.followed_samples) << kHistoryFollowedShift);
  return Resolved(vec4(h.color.rgb, float(flags)), vec4(h.shadow, h.samples, h.nearest, h.farthest),
                  vec4(h.followed_color, h.followed_shadow));
}

#ifdef RTSDF_TAKES_HISTORY
// The History the keep pass handed on (history_handed_on); read before the
// resolve writes those images.
History handed_history(ivec2 pixel) {
  vec4 color = imageLoad(resolved_color, pixel), passes = imageLoad(resolved_passes, pixel);
  uint flags = uint(color.a);
  History h;
  h.disoccluded = (flags & kHistoryDisoccluded) != 0u;
  h.color = vec4(color.rgb, 0.0);
  h.shadow = passes.x;
  h.samples = passes.y;
  h.full_samples = 0.0;  // (only find_history's own test of `still` reads it)
  h.nearest = passes.z;
  h.farthest = passes.w;
  h.previous_depth = imageLoad(g_motion, pixel).z;
  h.on_ray = vec3(0.0);  // (likewise)
  h.front_moved = (flags & kHistoryFrontMoved) != 0u;
  h.stays = false;  // (only the keep pass reads it, history_may_be_short)
  h.still = (flags & kHistoryStill) != 0u;
  h.away = (flags & kHistoryAway) != 0u;
  h.shadow_may_move = (flags & kHistoryShadowMayMove) != 0u;
  vec4 followed = imageLoad(resolved_moments, pixel);
  h.followed_color = followed.rgb;
  h.followed_shadow = followed.a;
  h.followed_samples = float(flags >> kHistoryFollowedShift);
  h.followed_alone = (flags & kHistoryFollowedAlone) != 0u;
  h.shadow_carried = (flags & kHistoryShadowCarried) != 0u;
  return h;
}
#endif

// A settled pixel's resolved accumulation: history at this pixel as it was
// (a settled pixel is where it was, with its full samples), the same that
// a copy of history gives the pixels outside a playback step's region
// (native/screen_region.h).
Resolved settled(ivec2 pixel) {
  return Resolved(imageLoad(history_color, pixel), imageLoad(history_passes, pixel), imageLoad(history_moments, pixel));
}
