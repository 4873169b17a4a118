#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
// Packing a field, step 3: the texels of the bricks step 2
// (field_brick_slots.comp) listed, one work group per brick, in its slot.
// Texels are stored in fine voxels as half floats, two to a word; each
// invocation packs one row of 8. (Only stored bricks take a work group:
// lavapipe spends about as long on one that does nothing as on a few loads,
// and most of a grid is far from its surfaces.)
#include "shared.h"
#include "brick_layout.glsl.h"

layout(local_size_x = 64) in;
layout(binding = 0, r32f) uniform readonly image3D fine;
layout(std430, binding = 1) readonly buffer StoredBricks { uvec4 store_groups; uint stored_bricks[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer FieldWords { uint words[]; };
layout(push_constant) uniform Push { FieldPackPush pc; };

void main() {
  ivec3 count = bricks_of(pc.dims.xyz);
  uint entry = stored_bricks[gl_WorkGroupID.x], local = gl_LocalInvocationIndex;
  ivec3 brick = brick_at(entry, count);
  FieldWords store = FieldWords(pc.store.xy);
  uint slot = store.words[kBrickTableFirst + entry];
  // Row `local` of the brick (y = local % 8, z = local / 8): 8 texels, 4 words.
  ivec3 row = min(brick * int(kBrickCells) + ivec3(0, int(local % kBrickTexels), int(local / kBrickTexels)), pc.dims.xyz - 1);
  uint word = pc.store.w + slot * kBrickWords + local * (kBrickTexels / 2u);
  for (int x = 0; x < int(kBrickTexels); x += 2) {
    ivec3 a = ivec3(min(row.x + x, pc.dims.x - 1), row.yz), b = ivec3(min(row.x + x + 1, pc.dims.x - 1), row.yz);
    vec2 pair = vec2(imageLoad(fine, a).x, imageLoad(fine, b).x) / pc.fine_grid.w;
    store.words[word + uint(x / 2)] = packHalf2x16(clamp(pair, -kMaxPackedDistance, kMaxPackedDistance));
  }
}
