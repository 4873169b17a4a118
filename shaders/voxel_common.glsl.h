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

// Triangles whose bounding box spans under 2 voxels on every axis are marked
// by the compute splat (voxelize_splat.comp), one thread each; rasterizing
// them would cost llvmpipe a whole triangle setup for a few fragments. The
// vertex stage drops exactly these, so every triangle takes one path.
bool splat_sized(vec3 p0, vec3 p1, vec3 p2) {
  vec3 extent = max(max(p0, p1), p2) - min(min(p0, p1), p2);
  return all(lessThan(extent, vec3(2.0)));
}

// Separating-axis test of a triangle against the unit voxel centred at `center`
// (Akenine-Moeller 2001). Touching counts as overlapping, so thin and tiny
// triangles always mark the voxels they pass through.
bool overlaps_voxel(vec3 a, vec3 b, vec3 c, vec3 center) {
  const float h = 0.5 + 1e-4;
  vec3 v0 = a - center, v1 = b - center, v2 = c - center;
  if (any(greaterThan(min(min(v0, v1), v2), vec3(h))) || any(lessThan(max(max(v0, v1), v2), vec3(-h))))
    return false;
  vec3 e[3] = vec3[3](v1 - v0, v2 - v1, v0 - v2);
  vec3 n = cross(e[0], e[1]);
  if (abs(dot(n, v0)) > h * dot(abs(n), vec3(1.0))) return false;
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      vec3 unit = vec3(0.0);
      unit[k] = 1.0;
      vec3 axis = cross(unit, e[i]);
      float p0 = dot(axis, v0), p1 = dot(axis, v1), p2 = dot(axis, v2);
      float r = h * dot(abs(axis), vec3(1.0));
      if (min(min(p0, p1), p2) > r || max(max(p0, p1), p2) < -r) return false;
    }
  }
  return true;
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
