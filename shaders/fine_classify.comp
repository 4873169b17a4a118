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
// A still field (kFineStill) lists only the texels whose last trace
// still found a closer surface (history.x, see fine_trace.comp): the rest
// have converged, and tracing them again would change nothing.
// A work group per brick near the band (listed by fine_bricks_near.comp)
// classifies the texels it owns: no band texel lies in the other bricks, and
// no packed field reads their far values (its far field holds them). Most
// of a grid is such bricks, and a deforming mesh's field is classified anew
// every frame.
#include "shared.h"
#include "seed_common.glsl.h"  // texel indices are packed like seeds
#include "brick_layout.glsl.h"
#include "fine_history.glsl.h"

layout(local_size_x = 64) in;
layout(binding = 0, r32f) uniform readonly image3D coarse;
layout(binding = 1, r32f) uniform writeonly image3D fine;
layout(binding = 2, rgba32f) uniform image3D history;  // see fine_history.glsl.h
// Texels on their turn from the front, texels measured again off their
// turn (remeasure_count of them) from the back: the trace runs each kind in
// work groups of its own (on lavapipe a group's lanes all run a ray's
// traversal where one of them casts one).
layout(std430, binding = 3) buffer TraceList { uint trace_count; uint remeasure_count; uint trace_texels[]; };
layout(std430, binding = 4) readonly buffer BrickState { uvec2 bricks[]; };  // see fine_bricks_near.comp
layout(std430, binding = 5) readonly buffer NearBricks { uvec4 classify_groups; uint near_bricks[]; };
layout(push_constant) uniform Push { FinePush pc; };

#include "coarse_sample.glsl.h"

struct TexelBricks {
  uint owner;  // the first near brick of those holding the texel: the one whose group classifies it
  uint flags;  // their flags (kBrickNear*), or'ed
};

// The bricks holding texel p: a texel on a brick's first face along an
// axis is the last face of the brick before, too.
TexelBricks texel_bricks(ivec3 p, ivec3 count) {
  ivec3 brick = min(p / int(kBrickCells), count - 1);
  ivec3 shared_face = ivec3(greaterThan(p, ivec3(0))) * ivec3(equal(p, brick * int(kBrickCells)));
  TexelBricks bricks_of_p = TexelBricks(kNoBrick, 0u);
  for (int k = 0; k < 8; ++k) {
    ivec3 step = ivec3(k & 1, (k >> 1) & 1, k >> 2);
    if (any(greaterThan(step, shared_face))) continue;
    uint index = brick_index(brick - step, count), flags = bricks[index].y;
    if (bricks_of_p.owner == kNoBrick && (flags & kBrickNearNow) != 0u) bricks_of_p.owner = index;
    bricks_of_p.flags |= flags;
  }
  return bricks_of_p;
}

// `fresh`: the texel holds no history of this field (a first frame, or no
// brick of it was classified in the last update).
void classify(ivec3 p, bool fresh) {
  vec3 world = pc.fine_grid.xyz + (vec3(p) + 0.5) * pc.fine_grid.w;
  float c = sample_coarse(world);
  if (c <= pc.params.y) {
    // A fixed pseudo-random turn per texel spreads each frame's share evenly.
    uint turn = (uint(p.x) * 73856093u) ^ (uint(p.y) * 19349663u) ^ (uint(p.z) * 83492791u);
    // A fresh texel is traced whatever its turn: a field in which most
    // texels were never traced has no signs, and shadows through solids
    // come out half lit. After a change in part of the scene only texels
    // near it are traced (on their turn); the rest keep their converged values.
    bool focused = (uint(pc.state.y) & kFineFocused) != 0u;
    bool in_focus = all(greaterThanEqual(p, unpack_seed(pc.schedule.z))) && all(lessThanEqual(p, unpack_seed(pc.schedule.w)));
    bool my_turn = (turn + pc.schedule.y) % pc.schedule.x == 0u && (!focused || in_focus);
    bool still = (uint(pc.state.y) & kFineStill) != 0u;
    if (still && !fresh && my_turn) my_turn = history_improving(imageLoad(history, p));
    // In a field whose geometry changes between updates, every band texel
    // (in the focus) is listed every update: off its turn it casts no ray,
    // but measures its kept nearest triangles again in the new shape
    // (fine_remeasure.comp). Left as they were, a deforming mesh's texels off
    // their turn held the distances of up to K - 1 updates ago.
    bool remeasured = !still && !fresh && !my_turn && (!focused || in_focus);
    if (fresh || my_turn || remeasured) {
      uint slot = remeasured ? uint(trace_texels.length()) - 1u - atomicAdd(remeasure_count, 1u) : atomicAdd(trace_count, 1u);
      trace_texels[slot] = pack_seed(p);
      // (the trace reads history after a first frame: it starts here from
      // the upper bound a first frame's trace starts from)
      if (fresh && pc.coarse_dims.w == 0) imageStore(history, p, make_history(false, false, kNoTriangle, 0u, max(c + pc.params.z, 0.0), pc.params.w));
    }
  } else {
    float far_field = c + pc.state.x;
    imageStore(fine, p, vec4(far_field));
    imageStore(history, p, make_history(false, false, kNoTriangle, 0u, far_field, pc.params.w));
  }
}

void main() {
  ivec3 count = bricks_of(pc.fine_dims.xyz);
  uint index = near_bricks[gl_WorkGroupID.x];
  ivec3 brick = brick_at(index, count);
  ivec3 first = brick * int(kBrickCells);
  for (uint i = gl_LocalInvocationIndex; i < kBrickTexels * kBrickTexels * kBrickTexels; i += 64u) {
    ivec3 p = first + ivec3(i % kBrickTexels, (i / kBrickTexels) % kBrickTexels, i / (kBrickTexels * kBrickTexels));
    if (any(greaterThanEqual(p, pc.fine_dims.xyz))) continue;
    TexelBricks holding = texel_bricks(p, count);
    if (holding.owner == index) classify(p, pc.coarse_dims.w != 0 || (holding.flags & kBrickNearBefore) == 0u);
  }
}
