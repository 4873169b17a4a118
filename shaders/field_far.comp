#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
// Packing a field, step 1: the far field, the coarse distances plus beta
// (what the fine SDF holds away from surfaces, see fine_classify.comp) in
// fine voxels, as half floats: each invocation packs two neighbours along x
// into one word (rows have an even length; a row's last odd texel repeats).
#include "shared.h"

layout(local_size_x = RTSDF_GROUP_X, local_size_y = RTSDF_GROUP_Y, local_size_z = RTSDF_GROUP_Z) in;
layout(binding = 0, r32f) uniform readonly image3D coarse;
layout(buffer_reference, std430, buffer_reference_align = 4) writeonly buffer FieldWords { uint words[]; };
layout(push_constant) uniform Push { FieldPackPush pc; };

float far_value(ivec3 p) {
  float voxels = (imageLoad(coarse, p).x + pc.params.y) / pc.fine_grid.w;
  return clamp(voxels, -kMaxPackedDistance, kMaxPackedDistance);
}

void main() {
  ivec3 p = ivec3(gl_GlobalInvocationID) * ivec3(2, 1, 1);
  if (any(greaterThanEqual(p, pc.coarse_dims.xyz))) return;
  ivec3 next = ivec3(min(p.x + 1, pc.coarse_dims.x - 1), p.yz);
  uint index = uint(p.x + pc.coarse_dims.w * (p.y + pc.coarse_dims.y * p.z));
  FieldWords(pc.store.xy).words[pc.store.z + index / 2u] = packHalf2x16(vec2(far_value(p), far_value(next)));
}
