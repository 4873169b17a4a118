// G-buffer, vertex stage: an indexed draw per instance, vertices pulled from
// the scene's shared buffers (the index buffer is the scene's, so corners
// shared by triangles are transformed once).
//
// It hands on as few values as it can: lavapipe sets up every varying of
// every triangle, drawn or not, and a 110k-triangle mesh at 320x180 covers
// fewer pixels than it has triangles. The clip positions and the last
// frame's position follow from the world position, so the fragment stage
// makes them (exactly: they are affine in it).
// Included by gbuffer.vert with RTSDF_MATERIAL_INPUTS defined (the
// instance's material slots read per vertex: its slot, UV and colour), and
// by gbuffer_one_color.vert without, for an instance of one plain colour,
// which needs none of them. Outputs unused are still set up per triangle by
// lavapipe: the engine's G-buffer took about 3 ms longer with them.
// gbuffer_deforming.vert adds RTSDF_DEFORMATION, for an instance whose mesh
// deformed since the last frame: how far each vertex moved in the mesh (from
// where GpuScene::previous_positions() has it), in world space, so that the
// fragment stage's motion follows the deformation, not the instance alone.
#include "shared.h"

layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std140, binding = 1) uniform Frame { FrameData frame; };
layout(std430, binding = 2) readonly buffer Normals { float normals[]; };
layout(std430, binding = 3) readonly buffer Uvs { vec2 uvs[]; };
layout(std430, binding = 4) readonly buffer VertexMaterials { uint vertex_materials[]; };
layout(std430, binding = 7) readonly buffer VertexColors { float colors[]; };
layout(push_constant) uniform Push { GBufferPush pc; };

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_smooth_normal;  // (0,0,0) for flat meshes
#ifdef RTSDF_MATERIAL_INPUTS
layout(location = 2) out vec2 v_uv;
layout(location = 3) flat out uint v_slot;  // its material slot (the provoking vertex's counts)
layout(location = 4) out vec3 v_color;      // its colour attribute (white where the mesh has none)
#endif
#ifdef RTSDF_DEFORMATION
layout(std430, binding = 8) readonly buffer PreviousPositions { float previous_positions[]; };
layout(location = 5) out vec3 v_deformation;  // from where the vertex is to where it was in the mesh, placed as the instance is now
#endif

void main() {
  uint v = uint(gl_VertexIndex);  // (the mesh's base vertex included)
  vec4 object = vec4(positions[3u * v], positions[3u * v + 1u], positions[3u * v + 2u], 1.0);
  v_world = object * pc.object_to_world;
  // Normals transform by the inverse transpose, here as the cofactor matrix
  // (the inverse transpose times the determinant) with the determinant's sign:
  // the same directions without a matrix inverse per vertex.
  mat3 m = transpose(mat3(pc.object_to_world[0].xyz, pc.object_to_world[1].xyz, pc.object_to_world[2].xyz));
  mat3 cofactor = mat3(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1]));
  float orientation = dot(m[0], cofactor[0]) < 0.0 ? -1.0 : 1.0;
  v_smooth_normal = orientation * (cofactor * vec3(normals[3u * v], normals[3u * v + 1u], normals[3u * v + 2u]));
  gl_Position = frame.world_to_clip * vec4(v_world, 1.0);
#ifdef RTSDF_DEFORMATION
  vec3 was = vec3(previous_positions[3u * v], previous_positions[3u * v + 1u], previous_positions[3u * v + 2u]);
  v_deformation = vec4(was - object.xyz, 0.0) * pc.object_to_world;
#endif
#ifdef RTSDF_MATERIAL_INPUTS
  v_uv = uvs[v];
  v_slot = vertex_materials[v];
  v_color = vec3(colors[3u * v], colors[3u * v + 1u], colors[3u * v + 2u]);
#endif
}
