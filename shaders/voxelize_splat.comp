#version 450
#extension GL_GOOGLE_include_directive : require
// Voxelization of small triangles (see splat_sized): one thread per triangle
// tests the few voxels of its bounding box and marks those it overlaps.
#include "shared.h"
#include "seed_common.glsl.h"

layout(local_size_x = 64) in;
#include "voxel_common.glsl.h"
layout(binding = 2, r32ui) uniform writeonly uimage3D seeds;

void main() {
  uint triangle = gl_GlobalInvocationID.x;
  if (triangle >= pc.triangle_count) return;
  vec3 p0 = triangle_corner(triangle, 0u);
  vec3 p1 = triangle_corner(triangle, 1u);
  vec3 p2 = triangle_corner(triangle, 2u);
  if (!splat_sized(p0, p1, p2)) return;  // rasterized by voxelize.vert/.frag
  ivec3 lo = max(ivec3(floor(min(min(p0, p1), p2) - 1e-3)), ivec3(0));
  ivec3 hi = min(ivec3(floor(max(max(p0, p1), p2) + 1e-3)), pc.dims.xyz - 1);
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        ivec3 voxel = ivec3(x, y, z);
        if (overlaps_voxel(p0, p1, p2, vec3(voxel) + 0.5)) imageStore(seeds, voxel, uvec4(pack_seed(voxel)));
      }
}
