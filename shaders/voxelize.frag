#version 450
#extension GL_GOOGLE_include_directive : require
// Voxelization, fragment stage: every voxel in this pixel's column that the
// triangle really overlaps becomes a seed (its own packed index).
#include "shared.h"
#include "seed_common.glsl.h"
#include "voxel_common.glsl.h"

layout(binding = 2, r32ui) uniform writeonly uimage3D seeds;

layout(location = 0) flat in uint v_axis;
layout(location = 1) flat in vec4 v_clip_rect;


void main() {
  if (any(lessThan(gl_FragCoord.xy, v_clip_rect.xy)) || any(greaterThan(gl_FragCoord.xy, v_clip_rect.zw))) return;
  uint axis = v_axis;
  vec2 c = gl_FragCoord.xy - vec2(float(axis * uint(pc.dims.w)), 0.0);  // see voxelize.vert

  uint triangle = uint(gl_PrimitiveID);
  vec3 p0 = triangle_corner(triangle, 0u);
  vec3 p1 = triangle_corner(triangle, 1u);
  vec3 p2 = triangle_corner(triangle, 2u);
  vec3 q0 = to_view(p0, axis), q1 = to_view(p1, axis), q2 = to_view(p2, axis);

  // Depth range of the triangle's plane over this pixel's square, within the triangle's own range.
  float w_lo = min(min(q0.z, q1.z), q2.z);
  float w_hi = max(max(q0.z, q1.z), q2.z);
  vec3 n = cross(q1 - q0, q2 - q0);
  if (abs(n.z) > 1e-12) {
    float w_centre = q0.z - (n.x * (c.x - q0.x) + n.y * (c.y - q0.y)) / n.z;
    float spread = 0.5 * (abs(n.x) + abs(n.y)) / abs(n.z);
    w_lo = max(w_lo, w_centre - spread);
    w_hi = min(w_hi, w_centre + spread);
  }
  ivec3 view_dims = ivec3(to_view(vec3(pc.dims.xyz), axis));
  ivec2 uv = ivec2(floor(c));
  if (any(greaterThanEqual(uv, view_dims.xy))) return;
  int first = max(int(floor(w_lo - 1e-3)), 0);
  int last = min(int(floor(w_hi + 1e-3)), view_dims.z - 1);
  for (int w = first; w <= last; ++w) {
    ivec3 voxel = from_view(ivec3(uv, w), axis);
    if (overlaps_voxel(p0, p1, p2, vec3(voxel) + 0.5)) imageStore(seeds, voxel, uvec4(pack_seed(voxel)));
  }
}
