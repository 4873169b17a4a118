#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
// Shading, step 1: visibility for one pixel of each 2x2 quad (see
// shade_inputs.glsl.h), one invocation per quad: the world light's, and in a
// kShadeShared frame every light's too.
#define RTSDF_QUAD_PASS
#include "shared.h"

layout(local_size_x = 8, local_size_y = 8) in;
#include "shade_inputs.glsl.h"

void main() {
  ivec2 quad = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(quad, quad_grid()))) return;
  int quad_index = quad.x + quad_grid().x * quad.y;
  ivec2 pixel = quad_sample_pixel(quad);
  vec4 position = imageLoad(g_position, pixel);
  if (position.w <= 0.0) {
    imageStore(quad_samples, quad, vec4(0.0, 0.0, 0.0, -1.0));
    if (kShadeStage == kShadeShared)
      for (int l = 0; l < pc.light_count; ++l) quad_lights[l * quad_count() + quad_index] = -1.0;
    return;
  }
  vec3 p = position.xyz;
  vec3 n = facing_normal(pixel, p);
  float receiver_voxel = imageLoad(g_albedo, pixel).a;
  float jitter = hash(uvec3(pixel, pc.sequence));
  vec3 origin = march_origin(p, n, receiver_voxel);
  float sky = wants_sky() ? world_light_visibility(origin, n, receiver_voxel, jitter, pixel) : 1.0;
  imageStore(quad_samples, quad, vec4(n, sky));
  if (kShadeStage != kShadeShared) return;
  for (int l = 0; l < pc.light_count; ++l) {
    LightPath path = light_path(l, p, origin);
    float v = -1.0;
    if (faces_light(path, n)) v = march_light(path, origin, n, receiver_voxel, jitter, pixel);
    quad_lights[l * quad_count() + quad_index] = v;
  }
}
