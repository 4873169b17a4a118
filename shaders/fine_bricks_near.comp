#version 450
#extension GL_GOOGLE_include_directive : require
// Fine SDF, step 0: which bricks of the packed field (field_brick_slots.comp) lie
// near the band this update, one invocation per brick; the near ones are
// listed for the classify (fine_classify.comp). A brick is near when
// a coarse texel that its texels' coarse samples read lies in the band (a
// trilinear sample is never below all its corners): the test the packer
// stores bricks by, so every texel a stored brick holds is classified.
// Per brick: x = 1 + the last update it was near in (kept across updates),
// y = this update's flags (kBrickNearNow, kBrickNearBefore). Without kFineNearSurfaceOnly
// every brick is near (the whole dense fine SDF is kept up to date).
#include "shared.h"
#include "brick_layout.glsl.h"

layout(local_size_x = 64) in;
layout(binding = 0, r32f) uniform readonly image3D coarse;
layout(std430, binding = 1) buffer BrickState { uvec2 bricks[]; };
// The near bricks' indices, in any order, and the classify's dispatch: a work group for each.
layout(std430, binding = 2) buffer NearBricks { uvec4 classify_groups; uint near_bricks[]; };
layout(push_constant) uniform Push { FinePush pc; };

#include "brick_near_band.glsl.h"

void main() {
  ivec3 count = bricks_of(pc.fine_dims.xyz);
  uint index = gl_GlobalInvocationID.x;
  if (index >= uint(count.x * count.y * count.z)) return;
  ivec3 brick = brick_at(index, count);
  ivec3 first = brick * int(kBrickCells), last = min(first + int(kBrickCells), pc.fine_dims.xyz - 1);
  bool near = (uint(pc.state.y) & kFineNearSurfaceOnly) == 0u || brick_near_band(first, last, pc.params.y);
  // (x is 0 where no update marked it: the first update clears the buffer)
  uint last_near = bricks[index].x;
  bool near_before = pc.coarse_dims.w == 0 && last_near == pc.schedule.y;
  bricks[index] = uvec2(near ? pc.schedule.y + 1u : last_near, (near ? kBrickNearNow : 0u) | (near_before ? kBrickNearBefore : 0u));
  if (near) near_bricks[atomicAdd(classify_groups.x, 1u)] = index;
}
