#version 450
#extension GL_GOOGLE_include_directive : require
// Temporal reuse (the paper's TAA: reprojection and a neighbourhood clamp),
// run once after the shading of the first frame after a change: the frames
// accumulated before the change (history) are carried into the new
// accumulation where they still show the same surface, so that a frame of
// playback is not a single noisy sample.
// - The new sample is filtered over its surface first (filtered_sample).
// - Reprojection: the G-buffer's motion says where each pixel's surface point
//   was on screen in the last frame; history is read there, bilinearly.
// - Disocclusion: history whose depths there (the range its samples saw),
//   and within the jitter's reach around it, miss that point's depth from the
//   last camera (by more than depth_tolerance of it) shows another surface, and is
//   dropped; matched only within the reach, it counts as few samples.
// - Clamp: history is clipped to the box of this frame's 3x3 neighbourhood,
//   mean +- `clip` standard deviations in YCoCg (Salvi's variance clipping),
//   so that what changed (a moved shadow, a lit face) cannot linger.
// - Moved shadows: a moving shadow is not a moving surface. Where the path
//   to a light passes the box of the casters that moved, and this frame's
//   Shadow pass (filtered) is not history's, history stands for at most
//   moved_shadow_samples samples, however still the receiver, and is
//   clipped tighter (moved_shadow_clip): a reactive mask for the shadow.
// - Settled pixels: under unchanged lights and world, full history that stays
//   where it was, away from what moved, keeps its converged value; the new
//   sample is not blended in, so still parts of the image do not shimmer
//   during playback. Such a pixel near what moved (only its sky can change)
//   takes the new sample unclipped.
// The accumulation's running mean then goes on from history's samples
// (accum_passes.z), up to history_samples of them (kStillHistory times that
// for a settled pixel, and a still one away from contact with what moved).
#include "shared.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform Push { TemporalPush pc; };
layout(binding = 0, rgba32f) uniform readonly image2D g_position;
layout(binding = 1, rgba32f) uniform readonly image2D g_motion;
layout(binding = 2, rgba32f) uniform readonly image2D accum_color;   // this frame's sample
layout(binding = 3, rgba32f) uniform readonly image2D accum_passes;  // x = Depth (nearest), y = Shadow, z = samples (1), w = farthest depth
layout(binding = 4, rgba32f) uniform readonly image2D history_color;
layout(binding = 5, rgba32f) uniform readonly image2D history_passes;
layout(std430, binding = 6) readonly buffer Frame { FrameData frame; };
layout(std430, binding = 7) readonly buffer Lights { GpuLight lights[]; };
// The resolved accumulation (the renderer takes it as accum_* from here on).
layout(binding = 8, rgba32f) uniform writeonly image2D resolved_color;
layout(binding = 9, rgba32f) uniform writeonly image2D resolved_passes;
layout(binding = 10, rgba32f) uniform readonly image2D g_normal;
layout(binding = 11, rgba32f) uniform readonly image2D g_albedo;
#include "same_surface.glsl.h"
#include "ray_box.glsl.h"

vec3 to_ycocg(vec3 c) {
  return vec3(0.25 * c.r + 0.5 * c.g + 0.25 * c.b, 0.5 * c.r - 0.5 * c.b, -0.25 * c.r + 0.5 * c.g - 0.25 * c.b);
}
vec3 from_ycocg(vec3 c) { return vec3(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z); }

// Whether the paths from p to light l (a cone towards its disk) cross the
// box of the casters that moved: the box grown by the cone's radius there,
// against the cone's axis.
bool light_path_crosses_change(vec3 p, int l) {
  if (frame.changed_lo.w == 0.0) return false;
  GpuLight light = lights[l];
  bool sun = uint(light.position.w) == kLightSun;
  vec3 to_light = sun ? -light.direction.xyz : light.position.xyz - p;
  float t_max = sun ? 1e30 : 1.0;
  vec3 centre = 0.5 * (frame.changed_lo.xyz + frame.changed_hi.xyz);
  float cone = sun ? light.direction.w * (distance(p, centre) + length(frame.changed_hi.xyz - centre))
                   : light.direction.w;
  vec2 span = ray_box_span(p, safe_inverse(to_light), frame.changed_lo.xyz - cone, frame.changed_hi.xyz + cone);
  return max(span.x, 0.0) <= min(span.y, t_max);
}

// Where a still pixel near what moved is clipped as a moving one's: within
// this share of the changed box's size (its contact shadow, see main).
const float kContactReach = 0.25;

// How far this frame's Shadow pass may lie from history's where a moved
// caster's shadow may have moved, and history still count as unmoved.
const float kSameShadow = 0.02;

// The most samples a still pixel's history counts for, in history_samples:
// near what moved it goes on taking a new sample each frame, whose weight
// then falls as a still accumulation's would (its sky follows the motion
// more slowly than a moved shadow, which is clipped apart).
const float kStillHistory = 4.0;

// Whether p is within `distance` of the box lo, hi (lo.w = 0: an empty box).
bool within_box(vec3 p, vec4 lo, vec4 hi, float distance) {
  if (lo.w == 0.0) return false;
  vec3 outside = max(max(lo.xyz - p, p - hi.xyz), 0.0);
  return length(outside) <= distance;
}

// Whether p is within `reach` times the changed box's own size of it (at 1:
// the sky it sees may be what moved).
bool near_change(vec3 p, float reach) {
  return within_box(p, frame.changed_lo, frame.changed_hi, reach * length(frame.changed_hi.xyz - frame.changed_lo.xyz));
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

// This frame's sample at `pixel` (a surface point p) with its noise
// filtered: the light (colour over albedo) of the pixel and of the four
// pixels two out along the axes (weights 2 and 1: two out lies in the next
// 2x2 quad, whose world light is a sample of its own; the pixel next door
// shares much of this one's), times the pixel's albedo. Only neighbours on
// the same surface count, and the less the more their sun visibility (the
// Shadow pass) differs, so that a shadow's edge stays where it is. Where history stands for few samples (a
// moved shadow, a disocclusion), the one jittered sample would carry its
// marches' noise into the frame shown, and from frame to frame; the
// interleaved random numbers (sdf_march.glsl.h) give neighbours samples
// that complement each other.
const float kShadowEdge = 0.1;  // (the Shadow pass difference that divides a neighbour's weight by e)
vec3 filtered_sample(ivec2 pixel, vec3 p, vec3 current, inout float shadow) {
  vec3 albedo = imageLoad(g_albedo, pixel).rgb;
  if (any(lessThan(albedo, vec3(1e-3)))) return current;  // (no light to tell from the colour)
  vec3 n = imageLoad(g_normal, pixel).xyz;
  // The pixel itself (`current` and `shadow` are its own), then its neighbours.
  vec3 light = 2.0 * current / albedo;
  float shadows = 2.0 * shadow, weights = 2.0;
  const ivec2 kNeighbours[4] = ivec2[4](ivec2(2, 0), ivec2(-2, 0), ivec2(0, 2), ivec2(0, -2));
  for (int k = 0; k < 4; ++k) {
    ivec2 q = pixel + kNeighbours[k];
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, pc.image_size))) continue;
    vec4 at = imageLoad(g_position, q);
    vec3 a = imageLoad(g_albedo, q).rgb;
    if (at.w <= 0.0 || any(lessThan(a, vec3(1e-3)))) continue;
    vec3 normal = imageLoad(g_normal, q).xyz;
    if (!on_sample_surface(at.xyz, dot(normal, n) < 0.0 ? -normal : normal, p, n)) continue;
    float neighbour_shadow = imageLoad(accum_passes, q).y, edge = (neighbour_shadow - shadow) / kShadowEdge;
    float w = exp(-edge * edge);
    light += w * imageLoad(accum_color, q).rgb / a;
    shadows += w * neighbour_shadow;
    weights += w;
  }
  shadow = shadows / weights;
  return light / weights * albedo;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, pc.image_size))) return;
  vec4 current = imageLoad(accum_color, pixel);
  vec4 passes = imageLoad(accum_passes, pixel);
  vec4 motion = imageLoad(g_motion, pixel);
  vec4 position = imageLoad(g_position, pixel);
  imageStore(resolved_color, pixel, current);  // (where history cannot help: this sample alone)
  imageStore(resolved_passes, pixel, passes);
  bool background = position.w <= 0.0;
  bool surface = !background && position.w < 0.5 * (kShadedSurface + kHoldoutSurface);
  vec3 on_ray = position.xyz;  // a point on this pixel's camera ray (the background's: on the near plane)
  if (background) {
    // The world behind everything moves with the camera alone: where this
    // pixel's ray met the far plane (with none, as cameras from Blender
    // have, the ray's direction: a homogeneous point at infinity), seen
    // from the last camera. Through the one matrix made in double
    // precision: a camera that stays puts the background exactly where it
    // was, and it settles (an inverse in single precision of a projection
    // without far plane put it anywhere, and the horizon flickered).
    vec2 ndc = (vec2(pixel) + 0.5) / vec2(pc.image_size) * 2.0 - 1.0;
    vec4 near_point = inverse(frame.steady_world_to_clip) * vec4(ndc, 0.0, 1.0);
    vec4 before = frame.steady_clip_to_previous_clip * vec4(ndc, 1.0, 1.0);
    if (abs(near_point.w) < 1e-20 || before.w <= 0.0) return;
    on_ray = near_point.xyz / near_point.w;
    motion = vec4(before.xy / before.w - ndc, kNothingHitDepth, 1.0);
  }

  // Where the surface point was: pixel centre + motion (in pixels), read
  // bilinearly (nothing where it was behind the last camera).
  vec2 at = vec2(pixel) + 0.5 + motion.xy * 0.5 * vec2(pc.image_size) - 0.5;
  ivec2 base = ivec2(floor(at));
  vec2 f = at - vec2(base);
  vec4 history = vec4(0.0);
  float history_shadow = 0.0, history_samples = 1e30, full_samples = 1e30, weights = 0.0;
  float history_nearest = kNothingHitDepth, history_farthest = 0.0;
  for (int k = 0; k < 4 && motion.w > 0.0; ++k) {
    ivec2 corner = base + ivec2(k & 1, k >> 1);
    if (any(lessThan(corner, ivec2(0))) || any(greaterThanEqual(corner, pc.image_size))) continue;
    vec4 before = imageLoad(history_passes, corner);
    full_samples = min(full_samples, before.z);
    if (!saw_depth(before, motion.z)) {
      if (!near_depth(corner, motion.z)) continue;
      before.z = min(before.z, kNearbyHistorySamples);
    }
    vec2 bilinear = mix(1.0 - f, f, vec2(k & 1, k >> 1));
    float w = bilinear.x * bilinear.y;
    if (w <= 0.0) continue;
    history += w * imageLoad(history_color, corner);
    history_shadow += w * before.y;
    history_samples = min(history_samples, before.z);
    history_nearest = min(history_nearest, before.x);
    history_farthest = max(history_farthest, before.w);
    weights += w;
  }
  bool disoccluded = weights < 1e-3;
  history /= max(weights, 1e-3);
  history_shadow /= max(weights, 1e-3);

  // A silhouette's history holds the surfaces in front as well (its nearest
  // depth). Where that front surface was what moved, this pixel's history
  // mixes in an object that has left it: it is uncertain, and never settled.
  // (The same for the background: where an object moved off it, history
  // near its old outline still holds it.)
  bool front_moved = false;
  if (!disoccluded && history_nearest < kNothingHitDepth) {
    vec3 camera = frame.camera_position.xyz, forward = frame.camera_forward.xyz;
    vec3 ray = frame.camera_position.w > 0.5 ? forward : normalize(on_ray - camera);
    float depth = background ? kNothingHitDepth : dot(on_ray - camera, forward);
    vec3 history_front = on_ray + ray * ((history_nearest - dot(on_ray - camera, forward)) / max(dot(ray, forward), 1e-3));
    // (that front surface was seen within the jitter's reach of this pixel's
    // ray, read bilinearly: a moved object's lies in the box of what moved,
    // casting shadows or not, give or take that many pixels; a whole box's
    // size more took in the ground's far edge, and the horizon never settled)
    front_moved = history_nearest < depth * (1.0 - pc.depth_tolerance) &&
                  within_box(history_front, frame.moved_lo, frame.moved_hi,
                             (pc.jitter_reach + 2.0) * pixel_width_at(history_front));
  }
  bool shadow_moved = false;  // (it may have: the paths to a light cross the box of what moved)
  for (int l = 0; l < pc.light_count && !background && !disoccluded; ++l)
    if (light_path_crosses_change(position.xyz, l)) shadow_moved = true;
  // Still: under the same lights and world, full history that stays on
  // screen where it was, with no moved object in front of it before (and,
  // below, out of any moved shadow). A silhouette's new sample may see a
  // surface its history never did (the jitter goes on to offsets the still
  // frames did not take); away from what moved, that is the jitter, not
  // motion, so its full history counts here.
  bool still = pc.same_lighting == 1u && min(full_samples, float(pc.history_samples)) >= float(pc.history_samples) &&
               !front_moved && all(lessThan(abs(at - vec2(pixel)), vec2(1e-3)));
  // Settled: still and away from what moved (whose sky it may share): the
  // converged still image, which a new jittered sample would only make
  // shimmer from frame to frame (what the still accumulation stops doing
  // after its samples too).
  bool away = background || !near_change(position.xyz, 1.0);

  // This frame's sample and Shadow pass filtered (filtered_sample), but not
  // for a pixel settled whatever its shadow, most of a playback frame (one
  // call: lavapipe runs a call site's code in every lane of a group that
  // reaches it).
  float shadow = passes.y;
  if (surface && (disoccluded || shadow_moved || !still || !away))
    current.rgb = filtered_sample(pixel, position.xyz, current.rgb, shadow);
  if (disoccluded) {
    imageStore(resolved_color, pixel, current);
    return;
  }
  // Whether the shadow did move: this frame's sun visibility (filtered)
  // against history's. The box of what moved is a bound: most pixels whose
  // light paths cross it keep their shadow, and taking half of each frame's
  // new sample there made them shimmer.
  if (shadow_moved && abs(shadow - history_shadow) < kSameShadow) shadow_moved = false;
  still = still && !shadow_moved;
  bool settled = still && away;

  // The neighbourhood's mean and spread in YCoCg (this frame's samples, same coverage).
  vec3 mean = vec3(0.0), square = vec3(0.0);
  float count = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 q = clamp(pixel + ivec2(dx, dy), ivec2(0), pc.image_size - 1);
      vec3 c = to_ycocg(imageLoad(accum_color, q).rgb);
      mean += c, square += c * c, count += 1.0;
    }
  mean /= count;
  vec3 sigma = sqrt(max(square / count - mean * mean, 0.0));
  float clip = shadow_moved ? pc.moved_shadow_clip : pc.clip;
  vec3 lo = mean - clip * sigma, hi = mean + clip * sigma;
  // Clip towards the mean (not per channel), keeping history's hue where it can.
  vec3 h = to_ycocg(history.rgb), d = h - mean;
  vec3 reach = max(hi - mean, vec3(1e-6));
  float scale = max(max(abs(d.x) / reach.x, abs(d.y) / reach.y), abs(d.z) / reach.z);
  vec3 clipped = from_ycocg(scale > 1.0 ? mean + d / scale : h);
  // (the shadow pass follows the colour: clipped by the same share)
  float kept = scale > 1.0 ? 1.0 / scale : 1.0;
  float shadow_history = mix(passes.y, history_shadow, kept);

  bool slow = still && !near_change(position.xyz, kContactReach);
  float most = slow || settled ? kStillHistory * float(pc.history_samples) : float(pc.history_samples);
  float samples = min(history_samples, most);
  if (front_moved) samples = min(samples, kNearbyHistorySamples);
  if (shadow_moved) samples = min(samples, pc.moved_shadow_samples);
  float w = 1.0 / (samples + 1.0);  // this frame's sample's share
  if (settled) w = 0.0, clipped = history.rgb, shadow_history = history_shadow;
  // Still, but near what moved: only the sky it sees can change, and by a
  // share of it that grows slowly with the motion; the clip to this frame's
  // one-sample neighbourhood would only add that sample's noise (most of
  // playback's flicker), so history goes on unclipped and the sky follows
  // through the new samples' weight. At contact (within a quarter of the
  // box's size) the sky changes fast: clipped as any other pixel.
  else if (slow) clipped = history.rgb, shadow_history = history_shadow;
  imageStore(resolved_color, pixel, vec4(mix(clipped, current.rgb, w), current.a));
  // History's depths, moved as this surface point moved in depth since.
  float moved = background ? 0.0 : passes.x - motion.z;
  imageStore(resolved_passes, pixel, vec4(min(passes.x, history_nearest + moved), mix(shadow_history, passes.y, w),
                                          settled ? max(samples, float(pc.history_samples)) : samples + 1.0,
                                          max(passes.w, history_farthest + moved)));
}
