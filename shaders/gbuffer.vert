#version 450
#extension GL_GOOGLE_include_directive : require
// G-buffer, vertex stage: vertices pulled from the scene's shared buffers;
// each triangle carries its face normal.
#include "shared.h"

layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, binding = 1) readonly buffer Indices { uint indices[]; };
layout(std430, binding = 2) readonly buffer Frame { FrameData frame; };
layout(push_constant) uniform Push { GBufferPush pc; };

layout(location = 0) out vec3 v_world;
layout(location = 1) flat out vec3 v_normal;

vec3 world_corner(uint triangle, uint corner) {
  uint v = indices[pc.first_index + 3u * triangle + corner] + pc.base_vertex;
  return (pc.object_to_world * vec4(positions[3u * v], positions[3u * v + 1u], positions[3u * v + 2u], 1.0)).xyz;
}

void main() {
  uint triangle = uint(gl_VertexIndex) / 3u;
  vec3 a = world_corner(triangle, 0u), b = world_corner(triangle, 1u), c = world_corner(triangle, 2u);
  vec3 n = cross(b - a, c - a);
  v_normal = dot(n, n) > 0.0 ? normalize(n) : vec3(0.0, 0.0, 1.0);
  vec3 corners[3] = vec3[3](a, b, c);
  v_world = corners[uint(gl_VertexIndex) % 3u];
  gl_Position = frame.world_to_clip * vec4(v_world, 1.0);
}
