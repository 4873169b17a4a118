#version 450
#extension GL_GOOGLE_include_directive : require
// Adaptive sampling: after each accumulation frame from the one completing
// half the samples on (and 4 at least: the first few jittered samples leave
// much of a pixel unvisited, and a sub-pixel edge or a thin shadow may lie
// there), with the fields and shadow maps no longer changing. A pixel whose
// samples agree (one sample's standard deviation in Y, Co and Cg, from the
// running second moments, below noise_threshold of its brightness) has
// converged. The tiles holding a pixel that has not are listed
// (kept_tiles.glsl.h) for the next frame's shading, which runs there alone
// (a tile's converged pixels go on taking samples, at their true count);
// the renderer reads their flags back (its next G-buffer's rectangle, and
// whether any frame is left to draw). The pixels of a tile left out take no
// more, and count as sampled in full: a later change's keep pass takes
// their history as settled.
// Every pixel took each of those first frames' samples, history carried
// into the accumulation included: a moving surface's reprojected history
// stands for many samples, but its spread shows once its own samples differ.
#include "shared.h"

layout(local_size_x = kTemporalTile, local_size_y = kTemporalTile) in;  // (a work group per tested tile)
layout(push_constant) uniform Push { TemporalPush pc; };
layout(binding = 0, rgba32f) uniform readonly image2D accum_color;
layout(binding = 1, rgba32f) uniform image2D accum_passes;  // z: the samples its mean stands for
layout(binding = 2, rgba32f) uniform readonly image2D accum_moments;
layout(std430, binding = 3) buffer Tiles { uint tile_words[]; };
// The tiles it tests, a work group each (x + tiles across * y): those the
// frame shaded. A tile left out before has converged, or its pixels were
// kept from history, settled with their full samples.
layout(std430, binding = 4) readonly buffer TestedTiles { uint tested_tiles[]; };
#define RTSDF_LISTS_TILES
#include "kept_tiles.glsl.h"
#define RTSDF_NO_GBUFFER  // (the moments alone)
#include "sample_moments.glsl.h"

// Below this brightness (Y) the spread allowed stays this one's: a pixel in
// full shadow need not agree to a share of its own near-black.
const float kDarkestJudged = 0.1;

shared bool tile_short;  // (some pixel of this work group's tile has not converged)

void main() {
  uint across = uint(pixel_tiles().tiles.x), index = tested_tiles[gl_WorkGroupID.x];
  ivec2 tile = ivec2(index % across, index / across);
  ivec2 pixel = tile * int(kTemporalTile) + ivec2(gl_LocalInvocationID.xy);
  bool inside = all(lessThan(pixel, pc.image_size));
  if (gl_LocalInvocationIndex == 0u) tile_short = false;
  barrier();
  bool converged = true;
  if (inside) {
    vec3 mean = imageLoad(accum_color, pixel).rgb;
    vec3 sigma = sample_sigma(imageLoad(accum_moments, pixel), mean);
    float allowed = pc.noise_threshold * max(to_ycocg(mean).x, kDarkestJudged);
    converged = max(sigma.x, max(sigma.y, sigma.z)) <= allowed;
  }
  if (!converged) tile_short = true;
  barrier();
  if (!inside) return;
  if (tile_short) {
    if (gl_LocalInvocationIndex == 0u) list_tile(pixel_tiles(), tile);
    return;
  }
  vec4 passes = imageLoad(accum_passes, pixel);
  if (passes.z < float(pc.history_samples))
    imageStore(accum_passes, pixel, vec4(passes.xy, float(pc.history_samples), passes.w));
}
