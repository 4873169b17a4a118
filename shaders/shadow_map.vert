#version 450
#extension GL_GOOGLE_include_directive : require
// Shadow map (csm_evsm), vertex stage: a shadow caster seen from one tile's
// view. Vertices are pulled from the scene's shared buffers, as in the G-buffer.
#include "shared.h"

layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, binding = 1) readonly buffer Indices { uint indices[]; };
layout(std430, binding = 2) readonly buffer Tiles { ShadowTile tiles[]; };
layout(push_constant) uniform Push { ShadowMapPush pc; };

layout(location = 0) out float v_depth;  // linear depth along the view axis, 0 at near, 1 at far

void main() {
  uint v = indices[pc.first_index + uint(gl_VertexIndex)] + pc.base_vertex;
  vec3 world = (pc.object_to_world * vec4(positions[3u * v], positions[3u * v + 1u], positions[3u * v + 2u], 1.0)).xyz;
  ShadowTile tile = tiles[pc.tile];
  gl_Position = tile.world_to_clip * vec4(world, 1.0);
  // Linear (not the projection's z), as the shading computes it for receivers.
  v_depth = (dot(tile.depth_axis.xyz, world) + tile.depth_axis.w - tile.depth_range.x) * tile.depth_range.y;
}
