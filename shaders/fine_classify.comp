#version 450
#extension GL_GOOGLE_include_directive : require
// Fine SDF, step 1: every fine texel reads the coarse SDF at its centre.
// Texels within the band (c <= d) whose turn it is (one in K per frame, all
// on the first frame; after a local change only those in the focus box) are
// appended to the trace list. Texels outside take the coarse distance, as the
// paper does, but without the bias beta: c + beta, the distance between voxel
// and seed centres, is off by at most half a voxel diagonal either way, where
// c is always low. Soft shadows read this far field: penumbrae wider than the
// band came out too dark at their outer edge with c.
// A still field (coarse_beta.z = 1) lists only the texels whose last trace
// still found a closer surface (history.x, see fine_trace.comp): the rest
// have converged, and tracing them again would change nothing.
#include "shared.h"
#include "seed_common.glsl.h"  // texel indices are packed like seeds

layout(local_size_x = RTSDF_GROUP_X, local_size_y = RTSDF_GROUP_Y, local_size_z = RTSDF_GROUP_Z) in;
layout(binding = 0, r32f) uniform readonly image3D coarse;
layout(binding = 1, r32f) uniform writeonly image3D fine;
layout(binding = 2, rgba32f) uniform image3D history;  // see fine_trace.comp
layout(std430, binding = 3) buffer TraceList { uint trace_count; uint trace_texels[]; };
layout(push_constant) uniform Push { FinePush pc; };

#include "coarse_sample.glsl.h"

void main() {
  ivec3 p = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(p, pc.fine_dims.xyz))) return;
  vec3 world = pc.fine_grid.xyz + (vec3(p) + 0.5) * pc.fine_grid.w;
  float c = sample_coarse(world);
  if (c <= pc.params.y) {
    // A fixed pseudo-random turn per texel spreads each frame's share evenly.
    uint turn = (uint(p.x) * 73856093u) ^ (uint(p.y) * 19349663u) ^ (uint(p.z) * 83492791u);
    // The first frame traces every band texel: a field in which most texels
    // were never traced has no signs, and shadows through solids come out half lit.
    // After a change in part of the scene only texels near it are traced (on
    // their turn); the rest keep their converged values.
    bool focused = pc.coarse_beta.y != 0.0;
    bool in_focus = all(greaterThanEqual(p, unpack_seed(pc.schedule.z))) && all(lessThanEqual(p, unpack_seed(pc.schedule.w)));
    bool my_turn = (turn + pc.schedule.y) % pc.schedule.x == 0u && (!focused || in_focus);
    if (pc.coarse_beta.z != 0.0 && pc.coarse_dims.w == 0 && my_turn) my_turn = imageLoad(history, p).x != 0.0;
    if (pc.coarse_dims.w != 0 || my_turn) {
      uint slot = atomicAdd(trace_count, 1u);
      trace_texels[slot] = pack_seed(p);
    } else if (pc.coarse_dims.w != 0) {
      // First frame, not traced yet: start from the same upper bound a traced texel starts from.
      imageStore(fine, p, vec4(max(c + pc.params.z, 0.0)));
      imageStore(history, p, vec4(0.0, 0.0, max(c + pc.params.z, 0.0), pc.params.w));
    }
  } else {
    float far_field = c + pc.coarse_beta.x;
    imageStore(fine, p, vec4(far_field));
    imageStore(history, p, vec4(0.0, 0.0, far_field, pc.params.w));
  }
}
