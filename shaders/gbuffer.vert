#version 450
#extension GL_GOOGLE_include_directive : require
// G-buffer, vertex stage: vertices pulled from the scene's shared buffers;
// each triangle carries its face normal, and smooth meshes their vertex normals.
#include "shared.h"

layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, binding = 1) readonly buffer Indices { uint indices[]; };
layout(std430, binding = 2) readonly buffer Frame { FrameData frame; };
layout(std430, binding = 3) readonly buffer Normals { float normals[]; };
layout(push_constant) uniform Push { GBufferPush pc; };

layout(location = 0) out vec3 v_world;
layout(location = 1) flat out vec3 v_face_normal;
layout(location = 2) out vec3 v_smooth_normal;  // (0,0,0) for flat meshes

vec3 world_corner(uint triangle, uint corner) {
  uint v = indices[pc.first_index + 3u * triangle + corner] + pc.base_vertex;
  return (pc.object_to_world * vec4(positions[3u * v], positions[3u * v + 1u], positions[3u * v + 2u], 1.0)).xyz;
}

void main() {
  uint triangle = uint(gl_VertexIndex) / 3u;
  vec3 a = world_corner(triangle, 0u), b = world_corner(triangle, 1u), c = world_corner(triangle, 2u);
  vec3 n = cross(b - a, c - a);
  v_face_normal = dot(n, n) > 0.0 ? normalize(n) : vec3(0.0, 0.0, 1.0);
  vec3 corners[3] = vec3[3](a, b, c);
  uint corner = uint(gl_VertexIndex) % 3u;
  v_world = corners[corner];
  uint v = indices[pc.first_index + 3u * triangle + corner] + pc.base_vertex;
  vec3 normal = vec3(normals[3u * v], normals[3u * v + 1u], normals[3u * v + 2u]);
  v_smooth_normal = transpose(inverse(mat3(pc.object_to_world))) * normal;
  gl_Position = frame.world_to_clip * vec4(v_world, 1.0);
}
