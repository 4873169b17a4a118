#version 450
#extension GL_GOOGLE_include_directive : require
// G-buffer, fragment stage: world position (w = 1 where covered), shading
// normal (interpolated for smooth meshes, else the triangle's plane, from the
// screen derivatives of the position: shading turns it to face the camera),
// base colour with a = the world voxel size of the field holding the surface
// (0: only a receiver, in no field).
#include "shared.h"

layout(push_constant) uniform Push { GBufferPush pc; };
layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_smooth_normal;
layout(location = 0) out vec4 out_position;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_albedo;

void main() {
  out_position = vec4(v_world, 1.0);
  float smooth_length = length(v_smooth_normal);
  vec3 face = cross(dFdx(v_world), dFdy(v_world));
  vec3 face_normal = dot(face, face) > 0.0 ? normalize(face) : vec3(0.0, 0.0, 1.0);
  out_normal = vec4(smooth_length > 1e-6 ? v_smooth_normal / smooth_length : face_normal, 0.0);
  out_albedo = vec4(pc.base_color.rgb, pc.field_voxel);
}
