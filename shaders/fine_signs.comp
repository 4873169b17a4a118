#version 450
#extension GL_GOOGLE_include_directive : require
// Fine SDF, step 4: the texels whose sign the trace doubted
// (fine_trace.glsl.h: its rays' votes or its kept triangle's side contradict
// the sign it found last) take the generalized winding number's
// (winding_number.glsl.h). The trace lists them rather than summing there:
// on lavapipe a call site's code runs in every lane of a SIMD group one of
// whose lanes reaches it, so the few doubted texels (about 400 of a
// deforming character's 31,000 band texels a frame) made their neighbours
// pay for the sum too, 20 ms of each frame. Listed, they run together.
#include "shared.h"
#include "seed_common.glsl.h"  // texel indices are packed like seeds
#include "fine_history.glsl.h"

layout(local_size_x = RTSDF_TRACE_GROUP) in;
#include "ray_trace.glsl.h"
layout(binding = 4, r32f) uniform writeonly image3D fine;
layout(binding = 5, rgba32f) uniform image3D history;
layout(std430, binding = 6) readonly buffer Doubts { uint doubt_count; uint doubt_groups[3]; uint doubt_texels[]; };
#define RTSDF_WINDING_BINDING 7
#include "winding_number.glsl.h"
layout(push_constant) uniform Push { FinePush pc; };

void main() {
  uint item = gl_GlobalInvocationID.x;
  if (item >= min(doubt_count, uint(doubt_texels.length()))) return;
  ivec3 p = unpack_seed(doubt_texels[item]);
  vec3 world = pc.fine_grid.xyz + (vec3(p) + 0.5) * pc.fine_grid.w;
  bool inside = inside_scene(world);
  vec4 h = imageLoad(history, p);
  if (inside == history_inside(h)) return;  // (the trace wrote the sign it found last)
  uint triangle, instance;
  if (!history_kept_triangle(h, triangle, instance)) triangle = kNoTriangle;
  imageStore(history, p, make_history(history_improving(h), inside, triangle, instance, h.z, h.w));
  imageStore(fine, p, vec4(min(inside ? -h.z : h.z, h.w)));
}
