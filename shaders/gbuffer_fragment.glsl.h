// G-buffer, fragment stage: world position (w = kShadedSurface where covered,
// kHoldoutSurface where a holdout is seen), shading
// normal (interpolated for smooth meshes, else the triangle's plane, from the
// screen derivatives of the position: shading turns it to face the camera;
// w: the instance's history bit, see shared.h's kHistoryBits), base colour
// (the face's material slot: its colour, times the vertex colour where it
// takes that, or its image sampled at the UV) with a = the world voxel size
// of the field holding the surface (0: only a receiver, in no field), and
// motion: xy = where this surface point was on screen in the last frame,
// from where it is now (normalized device coordinates, both without the
// jitter), z = its depth from the last frame's camera, w = 1 (0: it was
// behind that camera).
//
// The slot comes from the vertex (GpuScene uploads a vertex shared by faces
// of several slots once per slot): read from gl_PrimitiveID instead, lavapipe
// took 150 ms instead of 20 for the G-buffer of the 110k-triangle CAD sample.
// Included by gbuffer.frag with RTSDF_MATERIAL_INPUTS defined, by
// gbuffer_one_color.frag without, and by gbuffer_deforming.frag with
// RTSDF_DEFORMATION too (as gbuffer_vertex.glsl.h).
#include "shared.h"
layout(push_constant) uniform Push { GBufferPush pc; };
layout(std140, binding = 1) uniform Frame { FrameData frame; };
layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_smooth_normal;
#ifdef RTSDF_MATERIAL_INPUTS
layout(location = 2) in vec2 v_uv;
layout(location = 3) flat in uint v_slot;
layout(location = 4) in vec3 v_color;
#endif
#ifdef RTSDF_DEFORMATION
layout(location = 5) in vec3 v_deformation;
#endif
layout(std430, binding = 5) readonly buffer Materials { GpuMaterial materials[]; };
layout(std430, binding = 6) readonly buffer Texels { uint texels[]; };
layout(location = 0) out vec4 out_position;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_albedo;
layout(location = 3) out vec4 out_motion;

vec3 srgb_to_linear(vec3 c) {
  return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

vec3 texel(GpuMaterial m, ivec2 at) {
  ivec2 size = ivec2(m.width, m.height);
  at -= size * ivec2(floor(vec2(at) / vec2(size)));  // (the image repeats, as Blender's Image Texture does by default)
  return srgb_to_linear(unpackUnorm4x8(texels[m.texel_first + uint(at.y) * m.width + uint(at.x)]).rgb);
}

// Bilinear, with no mipmaps: an image seen much smaller than its texels aliases.
vec3 sample_image(GpuMaterial m, vec2 uv) {
  vec2 at = uv * vec2(m.width, m.height) - 0.5;
  ivec2 corner = ivec2(floor(at));
  vec2 f = at - vec2(corner);
  vec3 bottom = mix(texel(m, corner), texel(m, corner + ivec2(1, 0)), f.x);
  vec3 top = mix(texel(m, corner + ivec2(0, 1)), texel(m, corner + ivec2(1, 1)), f.x);
  return mix(bottom, top, f.y);
}

vec3 base_color() {
#ifdef RTSDF_MATERIAL_INPUTS
  // (GBufferPass draws with the material inputs only instances with slots;
  // the count's test keeps `material_count - 1` from wrapping if one had none)
  if (pc.material_count == 0u) return pc.base_color.rgb;
  uint slot = min(v_slot, pc.material_count - 1u);
  GpuMaterial m = materials[pc.first_material + slot];
  if (m.width != 0u) return sample_image(m, v_uv);
  return m.vertex_color != 0u ? m.base_color.rgb * v_color : m.base_color.rgb;
#else
  return pc.base_color.rgb;
#endif
}

void main() {
  out_position = vec4(v_world, pc.base_color.w);
  float smooth_length = length(v_smooth_normal);
  vec3 face = cross(dFdx(v_world), dFdy(v_world));
  vec3 face_normal = dot(face, face) > 0.0 ? normalize(face) : vec3(0.0, 0.0, 1.0);
  out_normal = vec4(smooth_length > 1e-6 ? v_smooth_normal / smooth_length : face_normal, float(pc.history_bit));
  out_albedo = vec4(base_color(), pc.field_voxel);
  vec4 steady_clip = frame.steady_world_to_clip * vec4(v_world, 1.0);
  vec3 placed_now = v_world;  // this point of the surface as it was shaped in the last frame, placed as now
#ifdef RTSDF_DEFORMATION
  placed_now += v_deformation;
#endif
  vec3 previous_world = vec4(placed_now, 1.0) * pc.world_to_previous_world;
  vec4 previous_clip = frame.previous_world_to_clip * vec4(previous_world, 1.0);
  vec2 now = steady_clip.xy / steady_clip.w;
  vec2 before = previous_clip.xy / max(previous_clip.w, 1e-20);
  float previous_depth = dot(previous_world - frame.previous_camera_position.xyz, frame.previous_camera_forward.xyz);
  out_motion = vec4(before - now, previous_depth, previous_clip.w > 0.0 ? 1.0 : 0.0);
}
