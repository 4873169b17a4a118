#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
// Packing a field, step 2: one work group per brick of the fine grid. A
// brick is stored if one of its texels lies in the trace band (coarse
// distance at most d, as fine_classify.comp lists them): the texels the fine
// SDF traced. The others hold the far field's values, which the march reads
// from the far field instead. Texels are stored in fine voxels as half
// floats, two to a word. Slots past the store's room are not written (the
// host sees the count, makes room and packs again).
#include "shared.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 8) in;
layout(binding = 0, r32f) uniform readonly image3D coarse;
layout(binding = 1, r32f) uniform readonly image3D fine;
layout(buffer_reference, std430, buffer_reference_align = 4) buffer FieldWords { uint words[]; };
layout(push_constant) uniform Push { FieldPackPush pc; };

#include "coarse_sample.glsl.h"

shared uint in_band;
shared uint slot;
shared float texels[kBrickTexels * kBrickTexels * kBrickTexels];

void main() {
  ivec3 brick = ivec3(gl_WorkGroupID);
  ivec3 texel = min(brick * int(kBrickCells) + ivec3(gl_LocalInvocationID), pc.dims.xyz - 1);
  uint local = gl_LocalInvocationIndex;
  if (local == 0u) in_band = 0u;
  barrier();
  vec3 centre = pc.fine_grid.xyz + (vec3(texel) + 0.5) * pc.fine_grid.w;
  if (sample_coarse(centre) <= pc.params.x) atomicOr(in_band, 1u);
  texels[local] = clamp(imageLoad(fine, texel).x / pc.fine_grid.w, -kMaxPackedDistance, kMaxPackedDistance);
  barrier();
  FieldWords store = FieldWords(pc.store.xy);
  if (local == 0u) {
    slot = in_band != 0u ? atomicAdd(store.words[0], 1u) : kNoBrick;
    uvec3 bricks = gl_NumWorkGroups;
    uint entry = uint(brick.x) + bricks.x * (uint(brick.y) + bricks.y * uint(brick.z));
    store.words[kBrickTableFirst + entry] = slot < uint(pc.dims.w) ? slot : kNoBrick;
  }
  barrier();
  if (slot >= uint(pc.dims.w) || local >= kBrickWords) return;
  store.words[pc.store.w + slot * kBrickWords + local] = packHalf2x16(vec2(texels[2u * local], texels[2u * local + 1u]));
}
