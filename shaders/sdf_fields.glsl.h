// The distance fields the shadow march reads: every field's texels in one
// pool (x fastest), each field placed in the world by FieldInstances (one
// per placed mesh in the object-space design, a single one for the
// whole-scene fields), and a BVH over the instances' world boxes whose
// leaves list instances in field_instances order. Needs RTSDF_STACK.
#include "ray_box.glsl.h"

layout(std430, binding = 3) readonly buffer FieldTexels { float field_texels[]; };
layout(std430, binding = 11) readonly buffer FieldInstances { FieldInstance field_instances[]; };
layout(std430, binding = 12) readonly buffer FieldNodes { BvhNode field_nodes[]; };

#define RTSDF_MAX_NEARBY_FIELDS 16
#define RTSDF_FIELD_STACK 32
// The instances near the part of a ray being marched (see gather_fields).
uint nearby_fields[RTSDF_MAX_NEARBY_FIELDS];

float field_texel(uint first, ivec3 dims, ivec3 i) {
  return field_texels[first + uint(i.x + dims.x * (i.y + dims.y * i.z))];
}

const float kFarAway = 3.0e38;

// One placed field at a point q of its voxel space (the world point
// world_to_field maps there): (x) a distance in world units that is never
// more than the true one, for the march's steps; (y) the field's trilinear
// value inside its box, kFarAway outside it, for clearances (outside the box
// only bounds are known, and a loose bound darkens penumbrae: the box's
// margin keeps every surface far enough from its outside); (z) the world size
// of the field's voxel. The box is the part of the grid around what the field
// holds (a grid with room for motion reads only far values in the rest).
// Outside the box the step's bound is the distance to what the field holds
// (its box less the margin).
vec3 field_distance_at(FieldInstance f, vec3 q) {
  ivec3 dims = ivec3(f.texels.yzw);
  if (any(lessThan(q, f.box_lo.xyz)) || any(greaterThan(q, f.box_hi.xyz))) {
    float margin = f.scale.w;
    return vec3(length(q - clamp(q, f.box_lo.xyz + margin, f.box_hi.xyz - margin)) * f.scale.y, kFarAway, f.scale.z);
  }
  vec3 s = q - 0.5;
  vec3 base = floor(s);
  vec3 w = clamp(s - base, 0.0, 1.0);
  ivec3 top = dims - 1;
  ivec3 i0 = clamp(ivec3(base), ivec3(0), top), i1 = clamp(ivec3(base) + 1, ivec3(0), top);
  uint first = f.texels.x;
  float c00 = mix(field_texel(first, dims, ivec3(i0.x, i0.y, i0.z)), field_texel(first, dims, ivec3(i1.x, i0.y, i0.z)), w.x);
  float c10 = mix(field_texel(first, dims, ivec3(i0.x, i1.y, i0.z)), field_texel(first, dims, ivec3(i1.x, i1.y, i0.z)), w.x);
  float c01 = mix(field_texel(first, dims, ivec3(i0.x, i0.y, i1.z)), field_texel(first, dims, ivec3(i1.x, i0.y, i1.z)), w.x);
  float c11 = mix(field_texel(first, dims, ivec3(i0.x, i1.y, i1.z)), field_texel(first, dims, ivec3(i1.x, i1.y, i1.z)), w.x);
  float h = mix(mix(c00, c10, w.y), mix(c01, c11, w.y), w.z) * f.scale.x;
  return vec3(h, h, f.scale.z);
}

vec3 field_distance(uint index, vec3 world) {
  FieldInstance f = field_instances[index];
  return field_distance_at(f, (f.world_to_field * vec4(world, 1.0)).xyz);
}

// Gathers into nearby_fields the instances whose world box, grown by
// `reach`, the ray meets between t0 and t1. Returns how many, or -1 when more
// than RTSDF_MAX_NEARBY_FIELDS do (the list then holds the first that fit).
int gather_fields(vec3 origin, vec3 inv_dir, float t0, float t1, float reach) {
  int count = 0;
  uint stack[RTSDF_FIELD_STACK];
  int top = 0;
  stack[top++] = 0u;
  while (top > 0) {
    BvhNode node = field_nodes[stack[--top]];
    vec2 span = ray_box_span(origin, inv_dir, node.lo.xyz - reach, node.hi.xyz + reach);
    if (max(span.x, t0) > min(span.y, t1)) continue;
    if (node.count == 0u) {
      if (top + 2 <= RTSDF_FIELD_STACK) { stack[top++] = node.first; stack[top++] = node.first + 1u; }
      continue;
    }
    for (uint i = node.first; i < node.first + node.count; ++i) {
      if (count == RTSDF_MAX_NEARBY_FIELDS) return -1;
      nearby_fields[count++] = i;
    }
  }
  return count;
}

// The scene at a world point, over the first `count` gathered fields, as
// field_distance: the smallest step bound (x) and clearance (y), and the
// voxel (z) of the field nearest by either.
vec3 nearby_distance(vec3 world, int count) {
  vec3 best = vec3(kFarAway, kFarAway, 0.0);
  for (int k = 0; k < count; ++k) {
    vec3 d = field_distance(nearby_fields[k], world);
    if (d.x < best.x) best.xz = d.xz;
    best.y = min(best.y, d.y);
  }
  return best;
}
