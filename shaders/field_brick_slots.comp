#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
// Packing a field, step 2: which bricks of the fine grid are stored, one
// invocation per brick. A brick is stored if a coarse texel that its
// texels' coarse samples read lies in the trace band (at most d): every
// texel the fine SDF traced (a trilinear sample is never below all its
// corners) and a few more. The other bricks hold the far field's values,
// which the march reads from the far field instead. A stored brick takes
// the next slot (word 0 counts them) and is listed for step 3
// (field_bricks.comp); slots past the store's room are not listed (the host
// sees the count, makes room and packs again). The brick table gets each
// brick's slot, or kNoBrick.
#include "shared.h"
#include "brick_layout.glsl.h"

layout(local_size_x = 64) in;
layout(binding = 0, r32f) uniform readonly image3D coarse;
// The listed bricks' table entries, and step 3's dispatch: a work group for each.
layout(std430, binding = 1) buffer StoredBricks { uvec4 store_groups; uint stored_bricks[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer FieldWords { uint words[]; };
layout(push_constant) uniform Push { FieldPackPush pc; };

#include "brick_near_band.glsl.h"

void main() {
  ivec3 count = bricks_of(pc.dims.xyz);
  uint entry = gl_GlobalInvocationID.x;
  if (entry >= uint(count.x * count.y * count.z)) return;
  ivec3 brick = brick_at(entry, count);
  ivec3 first = brick * int(kBrickCells), last = min(first + int(kBrickCells), pc.dims.xyz - 1);
  FieldWords store = FieldWords(pc.store.xy);
  uint slot = brick_near_band(first, last, pc.params.x) ? atomicAdd(store.words[0], 1u) : kNoBrick;
  bool room = slot < uint(pc.dims.w);
  store.words[kBrickTableFirst + entry] = room ? slot : kNoBrick;
  if (room) stored_bricks[atomicAdd(store_groups.x, 1u)] = entry;
}
