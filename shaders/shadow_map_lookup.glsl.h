// The shadow-map methods' visibility (csm_evsm, csm_jitter): EVSM moments
// (evsm.glsl.h) filtered per pixel over a disk of taps, then Chebyshev's bound.
// - csm_evsm: the disk is as wide as the penumbra at this receiver, from the
//   mean depth of the blockers a first search finds (PCSS, Fernando 2005);
// - csm_jitter: depth tests (PCF) over a fixed disk of about a texel
//   (pc.map_filter_texels) of a sharp map whose origin moves over the light every
//   frame: the frames' mean is the penumbra.
// The disks turn with the pixel and the frame, so accumulation frames fill them in.
// Needs `pc` (ShadePush) declared before it.
#include "evsm.glsl.h"

layout(binding = 8, rgba32f) uniform readonly image2D shadow_atlas;  // EVSM moments
layout(std430, binding = 9) readonly buffer ShadowTiles { ShadowTile shadow_tiles[]; };
layout(std430, binding = 10) readonly buffer ShadowLights { ShadowLightTiles shadow_lights[]; };

const int kBlockerTaps = 16;
const int kFilterTaps = 16;
const float kReceiverBias = 1.5;  // texels' widths of depth a receiver may lie behind its own plane

// Bilinear sample of a tile's moments at `texel` (continuous, 0 to size across the tile).
vec4 shadow_moments(ShadowTile tile, vec2 texel) {
  int last = int(pc.shadow_map_tile_texels) - 1;
  vec2 q = clamp(texel - 0.5, vec2(0.0), vec2(last));
  ivec2 i0 = ivec2(floor(q)), i1 = min(i0 + 1, ivec2(last));
  vec2 f = q - vec2(i0);
  ivec2 o = tile.atlas.xy;
  vec4 a = mix(imageLoad(shadow_atlas, o + i0), imageLoad(shadow_atlas, o + ivec2(i1.x, i0.y)), f.x);
  vec4 b = mix(imageLoad(shadow_atlas, o + ivec2(i0.x, i1.y)), imageLoad(shadow_atlas, o + i1), f.x);
  return mix(a, b, f.y);
}

// The view depth (world units) of the nearest caster at a texel, unfiltered:
// the positive warp inverted.
float caster_depth(ShadowTile tile, vec2 texel) {
  ivec2 q = clamp(ivec2(floor(texel)), ivec2(0), ivec2(int(pc.shadow_map_tile_texels) - 1));
  float x = log(max(imageLoad(shadow_atlas, tile.atlas.xy + q).x, 1e-30)) / pc.evsm_exponents.x;  // in [-1, 1]
  return tile.depth_range.x + 0.5 * (x + 1.0) / tile.depth_range.y;
}

// Where `p` falls in a tile: texel (x, y) and view depth (z); w < 0: outside
// it (beyond its border margin, or beyond its far plane, where casters behind
// were not drawn).
vec4 tile_position(ShadowTile tile, vec3 p) {
  vec4 clip = tile.world_to_clip * vec4(p, 1.0);
  float size = float(pc.shadow_map_tile_texels), margin = float(tile.atlas.z);
  vec2 texel = (clip.xy / max(clip.w, 1e-20) * 0.5 + 0.5) * size;
  float depth = dot(tile.depth_axis.xyz, p) + tile.depth_axis.w;
  bool inside = clip.w > 0.0 && all(greaterThanEqual(texel, vec2(margin))) &&
                all(lessThanEqual(texel, vec2(size - margin))) && (depth - tile.depth_range.x) * tile.depth_range.y <= 1.0;
  return vec4(texel, depth, inside ? 1.0 : -1.0);
}

// The penumbra's radius in texels at a receiver at view depth `receiver`
// behind blockers at `blocker` (similar triangles through the light's edge).
float penumbra_texels(ShadowTile tile, float receiver, float blocker) {
  float gap = max(receiver - blocker, 0.0);
  float world = tile.light.y > 0.5 ? tile.light.x * gap / max(blocker, 1e-4) : tile.light.x * gap;
  return world / (tile.depth_range.z + tile.depth_range.w * max(receiver, 0.0));
}

// How the view depth of the receiver's plane (normal n) changes per texel
// along the tile's x and y, up to 4 texels' width per texel (grazing planes).
vec2 receiver_slope(ShadowTile tile, vec3 n, float texel_world) {
  mat4 m = tile.world_to_clip;  // (columns: its rows 0 and 1 point along the tile's x and y)
  vec3 x_axis = normalize(vec3(m[0][0], m[1][0], m[2][0])), y_axis = normalize(vec3(m[0][1], m[1][1], m[2][1]));
  float facing = dot(n, tile.depth_axis.xyz);  // < 0 where the plane faces the light
  float gentle = -sign(facing) / max(abs(facing), 0.2);
  // A step s across the tile stays on the plane with a depth change w where n . (s + w axis) = 0.
  return clamp(gentle * vec2(dot(n, x_axis), dot(n, y_axis)), -4.0, 4.0) * texel_world;
}

// Tap k of n on a unit disk (Vogel's spiral), turned by `turn` (0 to 1).
vec2 disk_tap(int k, int n, float turn) {
  float r = sqrt((float(k) + 0.5) / float(n));
  float angle = float(k) * 2.39996323 + 6.28318531 * turn;
  return r * vec2(cos(angle), sin(angle));
}

// The share of light `light` reaching `p`, from the first of its tiles (the
// finest cascade) that holds p clear of the filter's reach; 1 where none
// does. `casts`: p's surface is in the maps itself, so it is looked up a
// texel off along the normal. `to_light`: towards the light (for the slope bias).
float shadow_map_visibility(int light, vec3 p, vec3 n, vec3 to_light, bool casts, float jitter) {
  ShadowLightTiles range = shadow_lights[light];
  for (uint i = 0u; i < range.count; ++i) {
    ShadowTile tile = shadow_tiles[range.first + i];
    vec4 at = tile_position(tile, p);
    if (at.w < 0.0) continue;
    float texel_world = tile.depth_range.z + tile.depth_range.w * max(at.z, 0.0);
    if (casts) at = tile_position(tile, p + n * (pc.shadow_map_offset * texel_world));
    float reach = float(tile.atlas.z - 1);
    vec2 slope = receiver_slope(tile, n, texel_world);
    if (pc.map_filter_texels > 0.0) {
      // csm_jitter: percentage-closer filtering of the sharp map.
      float lit = 0.0;
      for (int k = 0; k < kFilterTaps; ++k) {
        vec2 offset = pc.map_filter_texels * disk_tap(k, kFilterTaps, jitter);
        lit += caster_depth(tile, at.xy + offset) < at.z + dot(slope, offset) - kReceiverBias * texel_world ? 0.0 : 1.0;
      }
      return lit / float(kFilterTaps);
    }
    // Blockers: casters nearer the light than the receiver's own plane there
    // (so a receiver sloped towards the light does not shadow itself), by
    // more than a texel or so, within a disk as wide as the penumbra of a
    // blocker at the casters' near side.
    float search = clamp(penumbra_texels(tile, at.z, tile.depth_range.x), 1.0, reach);
    float sum = 0.0, count = 0.0;
    for (int k = 0; k < kBlockerTaps; ++k) {
      vec2 offset = search * disk_tap(k, kBlockerTaps, jitter);
      float d = caster_depth(tile, at.xy + offset);
      if (d < at.z + dot(slope, offset) - kReceiverBias * texel_world) sum += d, count += 1.0;
    }
    if (count == 0.0) return 1.0;
    float radius = clamp(penumbra_texels(tile, at.z, sum / count), 1.0, reach);
    vec4 moments = vec4(0.0);
    for (int k = 0; k < kFilterTaps; ++k) moments += shadow_moments(tile, at.xy + radius * disk_tap(k, kFilterTaps, jitter));
    moments /= float(kFilterTaps);
    vec2 warped = evsm_warp((at.z - tile.depth_range.x) * tile.depth_range.y, pc.evsm_exponents);
    // The least variance: what a depth error of half a texel's width would
    // give (d warp / d world = c |warp| dx/d world, dx/d world = 2 / range).
    vec2 spread = pc.evsm_exponents * abs(warped) * (tile.depth_range.y * texel_world);
    float v = min(chebyshev_upper_bound(moments.xy, warped.x, spread.x * spread.x),
                  chebyshev_upper_bound(moments.zw, warped.y, spread.y * spread.y));
    // Light-bleeding reduction: the bound's low tail (light leaking through
    // overlapping occluders) is cut to full shadow.
    return clamp((v - pc.light_bleeding_reduction) / (1.0 - pc.light_bleeding_reduction), 0.0, 1.0);
  }
  return 1.0;
}
