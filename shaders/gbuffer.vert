#version 450
#extension GL_GOOGLE_include_directive : require
// G-buffer, vertex stage: an indexed draw per instance, vertices pulled from
// the scene's shared buffers (the index buffer is the scene's, so corners
// shared by triangles are transformed once).
#include "shared.h"

layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std140, binding = 1) uniform Frame { FrameData frame; };
layout(std430, binding = 2) readonly buffer Normals { float normals[]; };
layout(std430, binding = 3) readonly buffer PreviousTransforms { mat4 previous_transforms[]; };
layout(std430, binding = 4) readonly buffer Uvs { vec2 uvs[]; };
layout(std430, binding = 5) readonly buffer VertexMaterials { uint vertex_materials[]; };
layout(std430, binding = 8) readonly buffer VertexColors { float colors[]; };
layout(push_constant) uniform Push { GBufferPush pc; };

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_smooth_normal;  // (0,0,0) for flat meshes
layout(location = 2) out vec4 v_steady_clip;    // this frame's clip position without the jitter
layout(location = 3) out vec4 v_previous_clip;  // the same point of the mesh in the last frame
layout(location = 4) out vec3 v_previous_world;
layout(location = 5) out vec2 v_uv;
layout(location = 6) flat out uint v_slot;  // its material slot (the provoking vertex's counts)
layout(location = 7) out vec3 v_color;      // its colour attribute (white where the mesh has none)

void main() {
  uint v = uint(gl_VertexIndex);  // (the mesh's base vertex included)
  vec4 object = vec4(positions[3u * v], positions[3u * v + 1u], positions[3u * v + 2u], 1.0);
  v_world = (pc.object_to_world * object).xyz;
  // Normals transform by the inverse transpose, here as the cofactor matrix
  // (the inverse transpose times the determinant) with the determinant's sign:
  // the same directions without a matrix inverse per vertex.
  mat3 m = mat3(pc.object_to_world);
  mat3 cofactor = mat3(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1]));
  float orientation = dot(m[0], cofactor[0]) < 0.0 ? -1.0 : 1.0;
  v_smooth_normal = orientation * (cofactor * vec3(normals[3u * v], normals[3u * v + 1u], normals[3u * v + 2u]));
  gl_Position = frame.world_to_clip * vec4(v_world, 1.0);
  // (a deforming mesh's vertices are taken where they are now: its motion is its transform's)
  v_previous_world = (previous_transforms[pc.instance] * object).xyz;
  v_steady_clip = frame.steady_world_to_clip * vec4(v_world, 1.0);
  v_previous_clip = frame.previous_world_to_clip * vec4(v_previous_world, 1.0);
  v_uv = uvs[v];
  v_slot = vertex_materials[v];
  v_color = vec3(colors[3u * v], colors[3u * v + 1u], colors[3u * v + 2u]);
}
