#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
// Shading, step 1: visibility for one pixel of each 2x2 quad (see
// shade_inputs.glsl.h), one invocation per quad: the world light's, and in a
// kShadeShared frame every light's too.
// The world light's cones march only where they pass a field's box; half the
// quads or more (a ground's, looking away from the objects on it) need no
// march at all. SIMD lanes wait for the longest march of their group, so
// the quads whose cones do march are listed (in the fill list's binding) and
// marched by a kShadeSkyList pass over just those, packed together.
#define RTSDF_QUAD_PASS
#include "shared.h"

layout(local_size_x = kQuadGroup, local_size_y = kQuadGroup) in;  // (a listed group per work group, see kept_tiles.glsl.h)
#include "shade_inputs.glsl.h"

// The world light at a quad's sample (origin: its march start, n: its normal).
float quad_sky(ivec2 quad, vec3 origin, vec3 n, float receiver_voxel, float jitter, ivec2 pixel) {
  if (!wants_sky()) return 1.0;
  if (kVisibilityMode == kVisibilityRayTraced) return world_light_visibility(origin, n, receiver_voxel, jitter, pixel);
  float sky;
  if (sky_without_march(origin, n, receiver_voxel, pixel, sky)) return sky;
  list_for_next_pass(quad);
  return 0.0;  // (the kShadeSkyList pass writes it)
}

// A quad's sample on a surface at p (its pixel's position): its facing
// normal, the voxel of the field holding it and its march start.
void sample_surface(ivec2 pixel, vec3 p, out vec3 n, out float receiver_voxel, out vec3 origin) {
  n = facing_normal(pixel, p);
  receiver_voxel = imageLoad(g_albedo, pixel).a;
  origin = march_origin(p, n, receiver_voxel);
}

void main() {
  vec3 n, origin;
  float receiver_voxel;
  if (kShadeStage == kShadeSkyList) {
    ivec2 quad;
    if (!listed_for_this_pass(quad)) return;
    ivec2 pixel = quad_sample_pixel(quad);
    sample_surface(pixel, imageLoad(g_position, pixel).xyz, n, receiver_voxel, origin);
    imageStore(quad_samples, quad, vec4(n, sky_visibility(origin, n, receiver_voxel, march_jitter(pixel), pixel)));
    return;
  }
  ivec2 quad = pc.listed_tiles == 1u ? listed_tile(quad_groups()) * int(kQuadGroup) + ivec2(gl_LocalInvocationID.xy)
                                     : ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(quad, quad_grid()))) return;
  int quad_index = quad.x + quad_grid().x * quad.y;
  ivec2 pixel = quad_sample_pixel(quad);
  vec4 position = imageLoad(g_position, pixel);
  // A quad no pixel that shares its sample shades (shared_visibility: the
  // 4 x 4 pixels around it, all left unshaded) is not marched. (Its
  // own pixels alone would leave the next quad's pixels at a kept region's
  // edge without their neighbour's sample, and the fill pass marched each.)
  bool kept = pc.listed_tiles == 1u;
  for (int k = 0; k < 16 && kept; ++k)
    kept = left_unshaded(clamp(2 * quad + ivec2(k & 3, k >> 2) - 1, ivec2(0), pc.image_size - 1));
  if (position.w <= 0.0 || kept) {
    imageStore(quad_samples, quad, vec4(0.0, 0.0, 0.0, -1.0));
    if (kShadeStage == kShadeShared)
      for (int l = 0; l < pc.light_count; ++l) quad_lights[l * quad_count() + quad_index] = -1.0;
    return;
  }
  vec3 p = position.xyz;
  sample_surface(pixel, p, n, receiver_voxel, origin);
  float jitter = march_jitter(pixel);
  imageStore(quad_samples, quad, vec4(n, quad_sky(quad, origin, n, receiver_voxel, jitter, pixel)));
  if (kShadeStage != kShadeShared) return;
  for (int l = 0; l < pc.light_count; ++l) {
    LightPath path = light_path(l, p, origin);
    float v = -1.0;
    if (faces_light(path, n)) v = march_light(path, origin, n, receiver_voxel, jitter, pixel);
    quad_lights[l * quad_count() + quad_index] = v;
  }
}
