#version 450
#extension GL_GOOGLE_include_directive : require
// G-buffer, fragment stage: world position (w = kShadedSurface where covered,
// kHoldoutSurface where a holdout is seen), shading
// normal (interpolated for smooth meshes, else the triangle's plane, from the
// screen derivatives of the position: shading turns it to face the camera),
// base colour with a = the world voxel size of the field holding the surface
// (0: only a receiver, in no field), and motion: xy = where this surface
// point was on screen in the last frame, from where it is now (normalized
// device coordinates, both without the jitter), z = its depth from the last
// frame's camera, w = 1 (0: it was behind that camera).
#include "shared.h"

layout(push_constant) uniform Push { GBufferPush pc; };
layout(std430, binding = 1) readonly buffer Frame { FrameData frame; };
layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_smooth_normal;
layout(location = 2) in vec4 v_steady_clip;
layout(location = 3) in vec4 v_previous_clip;
layout(location = 4) in vec3 v_previous_world;
layout(location = 0) out vec4 out_position;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_albedo;
layout(location = 3) out vec4 out_motion;

void main() {
  out_position = vec4(v_world, pc.base_color.w);
  float smooth_length = length(v_smooth_normal);
  vec3 face = cross(dFdx(v_world), dFdy(v_world));
  vec3 face_normal = dot(face, face) > 0.0 ? normalize(face) : vec3(0.0, 0.0, 1.0);
  out_normal = vec4(smooth_length > 1e-6 ? v_smooth_normal / smooth_length : face_normal, 0.0);
  out_albedo = vec4(pc.base_color.rgb, pc.field_voxel);
  vec2 now = v_steady_clip.xy / v_steady_clip.w;
  vec2 before = v_previous_clip.xy / max(v_previous_clip.w, 1e-20);
  float previous_depth = dot(v_previous_world - frame.previous_camera_position.xyz, frame.previous_camera_forward.xyz);
  out_motion = vec4(before - now, previous_depth, v_previous_clip.w > 0.0 ? 1.0 : 0.0);
}
