#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
// Shading, step 1: the world light's visibility for one pixel of each 2x2
// quad (see shade_inputs.glsl.h), one invocation per quad.
#define RTSDF_SKY_PASS
#include "shared.h"

layout(local_size_x = 8, local_size_y = 8) in;
#include "shade_inputs.glsl.h"

void main() {
  ivec2 quad = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(quad, (pc.image.xy + 1) / 2))) return;
  ivec2 pixel = sky_sample_pixel(quad);
  vec4 position = imageLoad(g_position, pixel);
  if (position.w <= 0.0) {
    imageStore(sky_samples, quad, vec4(0.0, 0.0, 0.0, -1.0));
    return;
  }
  vec3 n = facing_normal(pixel, position.xyz);
  float receiver_voxel = imageLoad(g_albedo, pixel).a;
  float jitter = hash(uvec3(pixel, uint(pc.image.w)));
  float sky = sky_visibility(march_origin(position.xyz, n, receiver_voxel), n, receiver_voxel, jitter, pixel);
  imageStore(sky_samples, quad, vec4(n, sky));
}
