#version 450
#extension GL_GOOGLE_include_directive : require
// Temporal reuse, before the shading of the first frame after a change: the
// pixels whose history stands whatever this frame's sample would be
// (settled_before_sample: still, beyond contact with what moved and out of
// its shadow's way) are resolved here (history as it was), and take history
// as their sample, marked kKeptSample: the shading passes skip them, the
// resolve (temporal_resolve.comp) leaves them, and their neighbours' clip
// and filter there see converged values in place of one noisy sample. In a
// playback step with the camera still, most of the image is such pixels:
// the step shades only where something changed. It runs over a list of
// tiles that holds every pixel it would not keep (native/screen_region.h:
// the shape of the change on screen); outside them the renderer copies
// history whole. It also marks the pixels whose history may stand for one
// sample or none (kShortHistorySample): their sample, most of what they
// show, takes more exact rays.
#include "shared.h"

layout(local_size_x = kTemporalTile, local_size_y = kTemporalTile) in;  // (a work group per tile)
layout(push_constant) uniform Push { TemporalPush pc; };
layout(binding = 0, rgba32f) uniform readonly image2D g_position;
layout(binding = 1, rgba32f) uniform readonly image2D g_motion;
layout(binding = 2, rgba32f) uniform writeonly image2D accum_color;   // this frame's sample
layout(binding = 3, rgba32f) uniform writeonly image2D accum_passes;  // z < 0 (kKeptSample): kept
layout(binding = 4, rgba32f) uniform readonly image2D history_color;
layout(binding = 5, rgba32f) uniform readonly image2D history_passes;
layout(std140, binding = 6) uniform Frame { FrameData frame; };
layout(std430, binding = 7) readonly buffer Lights { GpuLight lights[]; };
layout(binding = 8, rgba32f) uniform writeonly image2D resolved_color;
layout(binding = 9, rgba32f) uniform writeonly image2D resolved_passes;
layout(std430, binding = 10) buffer Tiles { uint tile_words[]; };
layout(binding = 11, rgba32f) uniform readonly image2D g_normal;
layout(binding = 12, rgba32f) uniform readonly image2D g_albedo;
layout(binding = 13, rgba32f) uniform readonly image2D history_moments;
layout(binding = 14, rgba32f) uniform writeonly image2D resolved_moments;
// The tiles it runs over, a work group each (x + tiles across * y).
layout(std430, binding = 15) readonly buffer KeepTiles { uint keep_tiles[]; };
#define RTSDF_LISTS_TILES
#include "sample_moments.glsl.h"  // (the instances a pixel's samples saw)
#include "temporal_history.glsl.h"

void main() {
  uint across = uint(pixel_tiles().tiles.x), index = keep_tiles[gl_WorkGroupID.x];
  ivec2 tile = ivec2(index % across, index / across);
  ivec2 pixel = tile * int(kTemporalTile) + ivec2(gl_LocalInvocationID.xy);
  if (any(greaterThanEqual(pixel, pc.image_size))) return;
  vec4 position = imageLoad(g_position, pixel);
  History h = find_history(pixel, position);
  bool kept = settled_before_sample(h);
  // Kept: resolved here, and its sample (for its neighbours in the resolve;
  // the passes as the shading would write them). Else shaded as usual, and
  // its History handed on to the resolve.
  Resolved r;
  if (kept)
    r = Resolved(h.own_color, h.own_passes, h.own_moments);  // (settled(pixel), as find_history read it)
  else
    r = history_handed_on(h);
  float seen = seen_depth(position);
  imageStore(resolved_color, pixel, r.color);
  imageStore(resolved_passes, pixel, r.passes);
  imageStore(resolved_moments, pixel, r.moments);
  bool short_history = !kept && history_may_be_short(h);
  float mark = kept ? kKeptSample : (short_history ? kShortHistorySample : 0.0);
  if (short_history) atomicAdd(tile_words[kShortHistoryCountWord], 1u);
  imageStore(accum_passes, pixel, kept ? vec4(seen, h.shadow, mark, seen) : vec4(0.0, 0.0, mark, 0.0));
  if (kept) {
    imageStore(accum_color, pixel, h.color);
  } else {
    list_tile(pixel_tiles(), tile);  // (for the pixel passes and the resolve; the next step's region holds them)
  }
}
