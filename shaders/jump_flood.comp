#version 450
#extension GL_GOOGLE_include_directive : require
// One jump-flooding pass: every voxel looks at the 26 voxels `step` away (and
// itself) and keeps the seed nearest to its own centre.
#include "shared.h"
#include "seed_common.glsl.h"

layout(local_size_x = RTSDF_GROUP_X, local_size_y = RTSDF_GROUP_Y, local_size_z = RTSDF_GROUP_Z) in;
layout(binding = 0, r32ui) uniform readonly uimage3D seeds_in;
layout(binding = 1, r32ui) uniform writeonly uimage3D seeds_out;
layout(push_constant) uniform Push { JumpFloodPush pc; };


void main() {
  ivec3 p = ivec3(gl_GlobalInvocationID);
  ivec3 dims = pc.dims.xyz;
  if (any(greaterThanEqual(p, dims))) return;
  int step = pc.dims.w;

  uint best = imageLoad(seeds_in, p).x;
  int best_d2 = 0x7fffffff;
  if (best != kNoSeed) { ivec3 d = unpack_seed(best) - p; best_d2 = d.x * d.x + d.y * d.y + d.z * d.z; }
  for (int z = -1; z <= 1; ++z) {
    for (int y = -1; y <= 1; ++y) {
      for (int x = -1; x <= 1; ++x) {
        ivec3 q = p + ivec3(x, y, z) * step;
        if ((x | y | z) == 0 || any(lessThan(q, ivec3(0))) || any(greaterThanEqual(q, dims))) continue;
        uint s = imageLoad(seeds_in, q).x;
        if (s == kNoSeed) continue;
        ivec3 d = unpack_seed(s) - p;
        int d2 = d.x * d.x + d.y * d.y + d.z * d.z;
        if (d2 < best_d2) { best_d2 = d2; best = s; }
      }
    }
  }
  imageStore(seeds_out, p, uvec4(best));
}
