#version 450
#extension GL_GOOGLE_include_directive : require
// Shadow map (csm_evsm): one axis of the separable box blur of a tile's EVSM
// moments. The radius is fractional (the end taps weigh the fraction), so
// penumbrae widen smoothly with the light's size; taps clamp at the tile's
// border, so tiles of one atlas do not bleed into each other.
#include "shared.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform readonly image2D source;
layout(binding = 1, rgba32f) uniform writeonly image2D target;
layout(push_constant) uniform Push { EvsmBlurPush pc; };

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  int size = pc.source.z;
  if (any(greaterThanEqual(texel, ivec2(size)))) return;
  ivec2 axis = pc.source.w == 0 ? ivec2(1, 0) : ivec2(0, 1);
  float radius = pc.radius.x;
  int reach = int(ceil(radius + 0.5)) - 1;  // taps with a weight above zero
  vec4 sum = vec4(0.0);
  float weights = 0.0;
  for (int i = -reach; i <= reach; ++i) {
    float w = clamp(radius + 0.5 - abs(float(i)), 0.0, 1.0);
    ivec2 q = clamp(texel + axis * i, ivec2(0), ivec2(size - 1));
    sum += w * imageLoad(source, pc.source.xy + q);
    weights += w;
  }
  imageStore(target, pc.target.xy + texel, sum / weights);
}
