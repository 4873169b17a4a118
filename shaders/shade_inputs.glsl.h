// What the shading passes (sky.comp, shade.comp) read: the G-buffer, the
// frame, the push constants, the fields and their march, and the world
// light's samples; and how a pixel's surface is set up for the march.
layout(binding = 0, rgba32f) uniform readonly image2D g_position;
layout(binding = 1, rgba32f) uniform readonly image2D g_normal;
layout(binding = 2, rgba32f) uniform readonly image2D g_albedo;
layout(std430, binding = 5) readonly buffer Frame { FrameData frame; };
layout(push_constant) uniform Push { ShadePush pc; };
// The visibility this pipeline computes (kVisibility*; as pc.visibility.x): a
// constant, so that the compiler drops the other methods' code. (Lavapipe
// runs both sides of a branch under a mask: dead code costs every pixel.)
layout(constant_id = 0) const uint kVisibilityMode = kVisibilitySignedSdf;
#include "sdf_fields.glsl.h"  // bindings 3, 11: the fields marched
#include "sdf_march.glsl.h"
// The world light's visibility is low-frequency: sky.comp marches it for
// one pixel of each 2x2 quad (which one changes every frame, so that
// accumulation covers all four), and shade.comp takes it for every pixel from
// the quads around it on its own surface, marching its own only where none
// is (Unreal's distance-field AO is computed at reduced resolution and
// upsampled alike). One texel per quad: xyz = the sample's normal, w = its
// visibility (< 0: no surface at the sample's pixel).
#ifdef RTSDF_SKY_PASS
layout(binding = 12, rgba32f) uniform writeonly image2D sky_samples;
#else
layout(binding = 12, rgba32f) uniform readonly image2D sky_samples;
#endif

// Whether the world light is marched at all (the same for every pixel).
bool wants_sky() { return kVisibilityMode != kVisibilityShadowMaps && dot(frame.ambient.rgb, frame.ambient.rgb) > 0.0; }

// The pixel a quad's world-light sample is marched for this frame.
ivec2 sky_sample_pixel(ivec2 quad) {
  int frame_index = pc.image.w;
  return min(2 * quad + ivec2(frame_index & 1, (frame_index >> 1) & 1), pc.image.xy - 1);
}

// The camera-facing side's normal at a G-buffer pixel.
vec3 facing_normal(ivec2 pixel, vec3 p) {
  vec3 n = imageLoad(g_normal, pixel).xyz;
  vec3 to_camera = frame.camera_position.w > 0.5 ? -frame.camera_forward.xyz : frame.camera_position.xyz - p;
  return dot(n, to_camera) < 0.0 ? -n : n;
}

// Where the march starts off a surface at p (normal n) held by a field of
// world voxel receiver_voxel (0: in none): a nudge along the normal keeps a
// caster's march off its own surface (see shade.comp's main).
vec3 march_origin(vec3 p, vec3 n, float receiver_voxel) { return p + n * (pc.surface.x * receiver_voxel); }

// How far off a sample's tangent plane a point may lie and still be on its
// surface: a thousandth of its distance to the camera's plane.
float same_surface_distance(vec3 p) {
  return 1e-3 * abs(dot(p - frame.camera_position.xyz, frame.camera_forward.xyz)) + 1e-6;
}
