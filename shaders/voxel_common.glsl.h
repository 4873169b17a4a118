// Helpers shared by the voxelization vertex and fragment shaders.
// The triangle is pulled from storage buffers by index, so both stages see all
// three corners without a geometry shader.
layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, binding = 1) readonly buffer Indices { uint indices[]; };
layout(push_constant) uniform Push { VoxelizePush pc; };

vec3 triangle_corner(uint triangle, uint corner) {
  uint v = indices[pc.first_index + 3u * triangle + corner] + pc.base_vertex;
  vec4 p = vec4(positions[3u * v], positions[3u * v + 1u], positions[3u * v + 2u], 1.0);
  return (pc.object_to_voxel * p).xyz;
}

// The axis along which the triangle has its largest projected area: rasterizing
// it from there gives the most fragments and at most ~1.4 voxels of depth per pixel.
uint dominant_axis(vec3 n) {
  vec3 a = abs(n);
  if (a.x >= a.y && a.x >= a.z) return 0u;
  return a.y >= a.z ? 1u : 2u;
}

// Voxel-space point -> (u, v, w) with w along the projection axis.
vec3 to_view(vec3 p, uint axis) {
  if (axis == 0u) return p.yzx;
  if (axis == 1u) return p.zxy;
  return p.xyz;
}
ivec3 from_view(ivec3 q, uint axis) {
  if (axis == 0u) return q.zxy;
  if (axis == 1u) return q.yzx;
  return q.xyz;
}
