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
// - Noise: the accumulation keeps its samples' second moments
//   (sample_moments.glsl.h), so a still pixel knows its own noise, and
//   its clip allows for it.
// - Settled pixels: under unchanged lights and world, full history that stays
//   where it was, beyond contact with what moved (or within it, where this
//   frame's neighbourhood holds history) and out of its shadow's way, keeps
//   its converged value; the new sample is not blended in, so
//   still parts of the image do not shimmer during playback. Most of them
//   were kept before the shading (temporal_keep.comp) and not shaded.
// The accumulation's running mean then goes on from history's samples
// (accum_passes.z), up to history_samples of them.
#include "shared.h"

layout(local_size_x = kTemporalTile, local_size_y = kTemporalTile) in;  // (a work group per tile)
layout(push_constant) uniform Push { TemporalPush pc; };
layout(binding = 0, rgba32f) uniform readonly image2D g_position;
layout(binding = 1, rgba32f) uniform readonly image2D g_motion;
layout(binding = 2, rgba32f) uniform readonly image2D accum_color;   // this frame's sample
layout(binding = 3, rgba32f) uniform readonly image2D accum_passes;  // x = Depth (nearest), y = Shadow, z = samples (1), w = farthest depth
layout(binding = 4, rgba32f) uniform readonly image2D history_color;
layout(binding = 5, rgba32f) uniform readonly image2D history_passes;
layout(std140, binding = 6) uniform Frame { FrameData frame; };
layout(std430, binding = 7) readonly buffer Lights { GpuLight lights[]; };
// The resolved accumulation (the renderer takes it as accum_* from here on).
// (Listed tiles: they hold, until written, the History the keep pass handed on.)
layout(binding = 8, rgba32f) uniform image2D resolved_color;
layout(binding = 9, rgba32f) uniform image2D resolved_passes;
layout(std430, binding = 10) readonly buffer Tiles { uint tile_words[]; };
layout(binding = 11, rgba32f) uniform readonly image2D g_normal;
layout(binding = 12, rgba32f) uniform readonly image2D g_albedo;
layout(binding = 13, rgba32f) uniform readonly image2D history_moments;
layout(binding = 14, rgba32f) uniform image2D resolved_moments;  // (listed tiles: the followed shadow's history, handed on)
#include "sample_moments.glsl.h"
#include "same_surface.glsl.h"
#define RTSDF_TAKES_HISTORY
#include "temporal_history.glsl.h"
// 1: the keep pass ran; the resolve runs over the tiles it listed and takes
// the History it handed on (a pipeline of its own: the search for history
// is not compiled in).
layout(constant_id = 0) const uint kListedTiles = 0u;

// How far this frame's Shadow pass may lie from history's where a moved
// caster's shadow may have moved, and history still count as unmoved.
// (Not widened by the pixel's noise: a slowly moving penumbra's ends then
// kept their history, 2 of the 41 pixels restarted in
// TemporalTest.AShadowThatDidNotMoveKeepsItsHistory.)
const float kSameShadow = 0.02;

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
// shadow_spread: the standard deviation of the Shadow pass over the pixel
// and those neighbours (unweighted: this frame's noise there).
vec3 filtered_sample(ivec2 pixel, vec3 p, vec3 current, inout float shadow, out float shadow_spread) {
  vec3 albedo = imageLoad(g_albedo, pixel).rgb;
  shadow_spread = 0.0;
  if (any(lessThan(albedo, vec3(1e-3)))) return current;  // (no light to tell from the colour)
  vec3 n = imageLoad(g_normal, pixel).xyz;
  // The pixel itself (`current` and `shadow` are its own), then its neighbours.
  vec3 light = 2.0 * current / albedo;
  float shadows = 2.0 * shadow, weights = 2.0;
  float shadow_sum = shadow, shadow_squares = shadow * shadow, on_surface = 1.0;  // (unweighted: the spread)
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
    shadow_sum += neighbour_shadow, shadow_squares += neighbour_shadow * neighbour_shadow, on_surface += 1.0;
    weights += w;
  }
  shadow = shadows / weights;
  float mean_shadow = shadow_sum / on_surface;
  shadow_spread = sqrt(max(shadow_squares / on_surface - mean_shadow * mean_shadow, 0.0));
  return light / weights * albedo;
}

// The resolved accumulation of a pixel shaded this frame (its sample
// `current` and `passes`, at G-buffer `position`) with its History h.
Resolved resolve(ivec2 pixel, vec4 position, vec4 current, vec4 passes, History h) {
  vec4 sample_second = sample_moments(current.rgb);  // (the sample's own, before any filter)
  sample_second.w = float(surface_bits(pixel, position));
  bool background = position.w <= 0.0;
  bool surface = !background && position.w < 0.5 * (kShadedSurface + kHoldoutSurface);

  // This frame's sample and Shadow pass filtered (filtered_sample), but not
  // for a pixel settled whatever its shadow, most of a playback frame (one
  // call: lavapipe runs a call site's code in every lane of a group that
  // reaches it).
  float shadow = passes.y, shadow_spread = 0.0;
  if (surface && (h.disoccluded || h.shadow_may_move || !h.still || !h.away))
    current.rgb = filtered_sample(pixel, position.xyz, current.rgb, shadow, shadow_spread);
  if (h.disoccluded) return Resolved(current, passes, sample_second);  // (where history cannot help: this sample alone)
  // A moved shadow followed to where it was (follow_shadow) stands for its
  // own samples, clipped as a moving surface's history is. It is taken where
  // what moved alone can shadow the pixel (followed_alone), or where its
  // Shadow pass is nearer this frame's (filtered) than the receiver's own
  // history's: a shadow that did not move (a still caster's, whose path
  // passes the box of what moved) keeps that. (The noisy sample alone
  // picked the own history at a moving shadow's edge often enough to make
  // it speckle.) Where the two agree, the own history is kept: it may
  // settle, and the lit ground around a moving caster does not shimmer.
  bool followed = h.shadow_may_move && h.followed_samples > 0.0 && abs(h.followed_shadow - h.shadow) >= kSameShadow &&
                  (h.followed_alone || abs(shadow - h.followed_shadow) < abs(shadow - h.shadow));
  if (followed) {
    h.color.rgb = h.followed_color;
    h.shadow = h.followed_shadow;
    h.samples = h.followed_samples;
    h.still = false;
  }
  // History's second moments: a still pixel's are its own texel's (it
  // stays where it was on screen); a moving pixel's samples' spread is not
  // carried (its neighbourhood alone judges their noise).
  vec4 history_second = h.still ? imageLoad(history_moments, pixel) : sample_moments(h.color.rgb);
  // Whether the shadow did move: this frame's sun visibility (filtered)
  // against history's. The box of what moved is a bound: most pixels whose
  // light paths cross it keep their shadow, and taking half of each frame's
  // new sample there made them shimmer.
  // Where the shadow moved with its moving surface (shadow_carried), a
  // difference within this frame's noise (twice the spread of the Shadow
  // pass over the filter's pixels on this surface) is that noise. Beyond
  // it, history is another surface's (read across an edge of a moving
  // object, where a lit face meets one turned from the light) and is
  // restarted as a moved shadow's.
  float same_shadow = kSameShadow + (h.shadow_carried ? 2.0 * shadow_spread : 0.0);
  bool shadow_moved = h.shadow_may_move && !followed && abs(shadow - h.shadow) >= same_shadow;
  bool still = h.still && !shadow_moved;
  if (still && h.away) return settled(pixel);

  // The neighbourhood's mean and spread in YCoCg (this frame's samples, same coverage).
  // For a still pixel the spread stands for the samples' noise, which decides
  // whether its history holds (below). The world light is marched at one
  // pixel of each 2x2 quad and shared by the pixels around it
  // (quad_share.glsl.h): a pixel's 3x3 neighbours hold few independent
  // samples of it, and their spread is narrower than the noise. So a still
  // pixel takes samples a quad apart: playback flicker 35-67% lower on six
  // bench scenes (sphere_plane 0.000060 -> 0.000021, character 0.000012 ->
  // 0.000004), the same on interior and room, the shown frame's error within
  // 0.2%. A moving pixel's clip stays tight (3x3), against ghosting.
  vec3 mean = vec3(0.0), square = vec3(0.0);
  float count = 0.0;
  int stride = still ? 2 : 1;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 q = clamp(pixel + stride * ivec2(dx, dy), ivec2(0), pc.image_size - 1);
      vec3 c = to_ycocg(imageLoad(accum_color, q).rgb);
      mean += c, square += c * c, count += 1.0;
    }
  mean /= count;
  vec3 sigma = sqrt(max(square / count - mean * mean, 0.0));
  // A still pixel's own samples tell its noise better: the world light's
  // two cones give near-discrete values, and nine neighbours' often agree
  // exactly (a spread of 0) where the pixel's do not over frames. A spread
  // below that noise clipped history that had not changed, and the new
  // sample blended in made the speckle of playback flicker.
  if (still) sigma = max(sigma, sample_sigma(history_second, h.color.rgb));
  float clip = shadow_moved ? pc.moved_shadow_clip : pc.clip;
  vec3 lo = mean - clip * sigma, hi = mean + clip * sigma;
  // Clip towards the mean (not per channel), keeping history's hue where it can.
  vec3 y = to_ycocg(h.color.rgb), d = y - mean;
  vec3 reach = max(hi - mean, vec3(1e-6));
  float scale = max(max(abs(d.x) / reach.x, abs(d.y) / reach.y), abs(d.z) / reach.z);
  vec3 clipped = from_ycocg(scale > 1.0 ? mean + d / scale : y);
  // A still pixel in contact with what moved (its sky may change fast):
  // where this frame's neighbourhood holds history (not clipped), nothing
  // shows a change beyond the samples' noise, and history keeps its
  // converged value. Blending each frame's new sample in at 1/(n+1) made
  // a speckle beside a moving caster from frame to frame (playback flicker
  // on sphere_plane 0.000077 -> 0.000060, and lower on four more bench
  // scenes; the shown frame's error the same or lower on 10 of 12). Where
  // the contact shadow did change, the clip moves history and the sample
  // is blended in, as before.
  if (still && scale <= 1.0) return settled(pixel);
  // (the shadow pass follows the colour: clipped by the same share)
  float kept = scale > 1.0 ? 1.0 / scale : 1.0;
  float shadow_history = mix(passes.y, h.shadow, kept);

  float samples = min(h.samples, float(pc.history_samples));
  if (h.front_moved) samples = min(samples, kNearbyHistorySamples);
  if (shadow_moved) samples = min(samples, pc.moved_shadow_samples);
  float w = 1.0 / (samples + 1.0);  // this frame's sample's share
  // History's depths, moved as this surface point moved in depth since.
  float moved = background ? 0.0 : passes.x - h.previous_depth;
  vec4 moments = mix(moments_moved_to(history_second, h.color.rgb, clipped), sample_second, w);
  // (the instances seen: this sample's, and history's where the surface stayed on its pixel, whose
  // moments history_second holds; a moving pixel's are made from its colour, with none)
  moments.w = float(surface_bits(pixel, position) | uint(history_second.w));
  return Resolved(vec4(mix(clipped, current.rgb, w), current.a),
                  vec4(min(passes.x, h.nearest + moved), mix(shadow_history, passes.y, w), samples + 1.0,
                       max(passes.w, h.farthest + moved)),
                  moments);
}

void main() {
  // Every tile, or those the keep pass listed: the rest it kept whole.
  ivec2 tile = kListedTiles == 1u ? listed_tile(pixel_tiles()) : ivec2(gl_WorkGroupID.xy);
  ivec2 pixel = tile * int(kTemporalTile) + ivec2(gl_LocalInvocationID.xy);
  if (any(greaterThanEqual(pixel, pc.image_size))) return;
  vec4 passes = imageLoad(accum_passes, pixel);
  if (passes.z == kKeptSample) return;  // (settled, and resolved by the keep pass)
  vec4 position = imageLoad(g_position, pixel);
  // (History handed on is read before the resolved images are written over it)
  History h = kListedTiles == 1u ? handed_history(pixel) : find_history(pixel, position);
  Resolved r = resolve(pixel, position, imageLoad(accum_color, pixel), passes, h);
  imageStore(resolved_color, pixel, r.color);
  imageStore(resolved_passes, pixel, r.passes);
  imageStore(resolved_moments, pixel, r.moments);
}
