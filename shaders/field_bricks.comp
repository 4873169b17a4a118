#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
// Packing a field, step 2: one work group per brick of the fine grid. A
// brick is stored if a coarse texel that its texels' coarse samples read
// lies in the trace band (at most d): every texel the fine SDF traced (a
// trilinear sample is never below all its corners) and a few more. The
// other bricks hold the far field's values, which the march reads from the
// far field instead. Texels are stored in fine voxels as half floats, two to
// a word; each invocation packs one row of 8. Slots past the store's room
// are not written (the host sees the count, makes room and packs again).
#include "shared.h"
#include "brick_layout.glsl.h"

layout(local_size_x = 64) in;
layout(binding = 0, r32f) uniform readonly image3D coarse;
layout(binding = 1, r32f) uniform readonly image3D fine;
layout(buffer_reference, std430, buffer_reference_align = 4) buffer FieldWords { uint words[]; };
layout(push_constant) uniform Push { FieldPackPush pc; };

shared uint in_band;
shared uint slot;

void main() {
  ivec3 brick = ivec3(gl_WorkGroupID);
  uint local = gl_LocalInvocationIndex;
  ivec3 first = brick * int(kBrickCells), last = min(first + int(kBrickCells), pc.dims.xyz - 1);
  if (local == 0u) in_band = 0u;
  barrier();
  ivec3 lo, hi;
  coarse_footprint(first, last, pc.fine_grid, pc.coarse_grid, pc.coarse_dims.xyz, lo, hi);
  ivec3 extent = hi - lo + 1;
  uint footprint = uint(extent.x * extent.y * extent.z);
  for (uint i = local; i < footprint; i += 64u) {
    ivec3 c = lo + ivec3(int(i) % extent.x, (int(i) / extent.x) % extent.y, int(i) / (extent.x * extent.y));
    if (imageLoad(coarse, c).x <= pc.params.x) atomicOr(in_band, 1u);
  }
  barrier();
  FieldWords store = FieldWords(pc.store.xy);
  if (local == 0u) {
    slot = in_band != 0u ? atomicAdd(store.words[0], 1u) : kNoBrick;
    uvec3 bricks = gl_NumWorkGroups;
    uint entry = uint(brick.x) + bricks.x * (uint(brick.y) + bricks.y * uint(brick.z));
    store.words[kBrickTableFirst + entry] = slot < uint(pc.dims.w) ? slot : kNoBrick;
  }
  barrier();
  if (slot >= uint(pc.dims.w)) return;
  // Row `local` of the brick (y = local % 8, z = local / 8): 8 texels, 4 words.
  ivec3 row = min(first + ivec3(0, int(local % kBrickTexels), int(local / kBrickTexels)), pc.dims.xyz - 1);
  uint word = pc.store.w + slot * kBrickWords + local * (kBrickTexels / 2u);
  for (int x = 0; x < int(kBrickTexels); x += 2) {
    ivec3 a = ivec3(min(row.x + x, pc.dims.x - 1), row.yz), b = ivec3(min(row.x + x + 1, pc.dims.x - 1), row.yz);
    vec2 pair = vec2(imageLoad(fine, a).x, imageLoad(fine, b).x) / pc.fine_grid.w;
    store.words[word + uint(x / 2)] = packHalf2x16(clamp(pair, -kMaxPackedDistance, kMaxPackedDistance));
  }
}
