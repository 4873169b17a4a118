#version 450
#extension GL_GOOGLE_include_directive : require
// Turns the flooded seed image into the coarse SDF: world distance from the
// voxel centre to its nearest seed's centre, minus beta (so surfaces thicken
// and get a negative inside).
#include "shared.h"
#include "seed_common.glsl.h"

layout(local_size_x = RTSDF_GROUP_X, local_size_y = RTSDF_GROUP_Y, local_size_z = RTSDF_GROUP_Z) in;
layout(binding = 0, r32ui) uniform readonly uimage3D seeds;
layout(binding = 1, r32f) uniform writeonly image3D distance_out;
layout(push_constant) uniform Push { SeedDistancePush pc; };


void main() {
  ivec3 p = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(p, pc.dims.xyz))) return;
  uint s = imageLoad(seeds, p).x;
  // No seed anywhere (an empty grid) reads as far away.
  float voxels = s == kNoSeed ? float(pc.dims.x + pc.dims.y + pc.dims.z) : length(vec3(unpack_seed(s) - p));
  imageStore(distance_out, p, vec4(voxels * pc.scale.x - pc.scale.y));
}
