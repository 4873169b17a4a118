// The distance fields the shadow march reads: each field's words (bricks
// near its surfaces, the far field elsewhere: see PackedField and
// shaders/shared.h) reached by its address, each field placed in the world
// by FieldInstances (one per placed mesh in the object-space design, a
// single one for the whole-scene fields), and a BVH over the instances'
// world boxes whose leaves list instances in field_instances order. Needs
// RTSDF_STACK, and GL_EXT_buffer_reference and GL_EXT_buffer_reference_uvec2
// enabled by the shader.
#include "ray_box.glsl.h"

layout(std430, binding = 3) readonly buffer FieldInstances { FieldInstance field_instances[]; };
layout(std430, binding = 11) readonly buffer FieldNodes { BvhNode field_nodes[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer FieldWords { uint words[]; };

#define RTSDF_MAX_NEARBY_FIELDS 16
#define RTSDF_FIELD_STACK 32
// The instances near the part of a ray being marched (see gather_fields),
// and for each where the ray leaves its leaf's box.
uint nearby_fields[RTSDF_MAX_NEARBY_FIELDS];
float nearby_exits[RTSDF_MAX_NEARBY_FIELDS];

// Texels `index` and `index + 1` of half floats packed from word `first` on
// (two words read either way: a select, not a branch, for SIMD lanes that differ).
vec2 texel_pair(FieldWords store, uint first, uint index) {
  uint word = first + (index >> 1u);
  vec2 a = unpackHalf2x16(store.words[word]), b = unpackHalf2x16(store.words[word + 1u]);
  return (index & 1u) == 0u ? a : vec2(a.y, b.x);
}

// The slot of the brick holding q's cell (q in the field's voxel space): at
// least f.dims.w where no brick is stored. `cell` is the cell whose 8 texels
// surround q (at the faces, the outer one), `brick` the brick holding it.
uint brick_slot(FieldInstance f, vec3 q, out ivec3 cell, out ivec3 brick) {
  FieldWords store = FieldWords(f.store.xy);
  ivec3 dims = f.dims.xyz;
  cell = clamp(ivec3(floor(q - 0.5)), ivec3(0), max(dims - 2, ivec3(0)));
  brick = cell / int(kBrickCells);
  ivec3 bricks = max(dims - 2, ivec3(0)) / int(kBrickCells) + 1;
  return store.words[kBrickTableFirst + uint(brick.x + bricks.x * (brick.y + bricks.y * brick.z))];
}

// The field at q (its voxel space, inside the grid), in its voxels: from
// the brick that holds q's cell where one is stored, else from the far
// field. Either is a block of half-float texels (x fastest) read by one
// trilinear fetch, so lanes of a SIMD step that read different ones do not
// diverge.
float field_value_at(FieldInstance f, vec3 q) {
  FieldWords store = FieldWords(f.store.xy);
  ivec3 cell, brick;  // (at the faces, weights clamp to the outer cell's texels)
  uint slot = brick_slot(f, q, cell, brick);
  bool stored = slot < uint(f.dims.w);
  // The far field: its grid shares the origin, with box_lo.w of its voxels per fine voxel.
  ivec3 far_dims = f.far_dims.xyz;
  vec3 far_q = q * f.box_lo.w;
  ivec3 far_cell = clamp(ivec3(floor(far_q - 0.5)), ivec3(0), max(far_dims - 2, ivec3(0)));
  ivec3 block_cell = stored ? cell - brick * int(kBrickCells) : far_cell;
  vec3 w = clamp((stored ? q : far_q) - 0.5 - vec3(stored ? cell : far_cell), 0.0, 1.0);
  // A far field one texel thick along an axis reads that texel twice.
  ivec3 step = stored ? ivec3(1) : min(far_cell + 1, far_dims - 1) - far_cell;
  if (step.x == 0) w.x = 0.0;
  uint row = stored ? kBrickTexels : uint(f.far_dims.w);
  uint slab = row * (stored ? kBrickTexels : uint(far_dims.y));
  uint first = stored ? f.store.w + slot * kBrickWords : f.store.z;
  uint t = uint(block_cell.x) + row * uint(block_cell.y) + slab * uint(block_cell.z);
  uint dy = row * uint(step.y), dz = slab * uint(step.z);
  vec2 y0z0 = texel_pair(store, first, t), y1z0 = texel_pair(store, first, t + dy);
  vec2 y0z1 = texel_pair(store, first, t + dz), y1z1 = texel_pair(store, first, t + dy + dz);
  float c00 = mix(y0z0.x, y0z0.y, w.x), c10 = mix(y1z0.x, y1z0.y, w.x);
  float c01 = mix(y0z1.x, y0z1.y, w.x), c11 = mix(y1z1.x, y1z1.y, w.x);
  return mix(mix(c00, c10, w.y), mix(c01, c11, w.y), w.z);
}

const float kFarAway = 3.0e38;

// One placed field at a point q of its voxel space (the world point
// world_to_field maps there): (x) outside the field's box, a distance in
// world units that is never more than the true one to what the field holds
// (its box less the margin), which bounds the march's steps; kFarAway inside;
// (y) the field's trilinear value inside its box, kFarAway outside it, for
// clearances (outside the box only bounds are known, and a loose bound
// darkens penumbrae: the box's margin keeps every surface far enough from its
// outside); (z) the world size of the field's voxel. The box is the part of
// the grid around what the field holds (a grid with room for motion reads
// only far values in the rest).
vec3 field_distance_at(FieldInstance f, vec3 q) {
  if (any(lessThan(q, f.box_lo.xyz)) || any(greaterThan(q, f.box_hi.xyz))) {
    float margin = f.scale.z;
    return vec3(length(q - clamp(q, f.box_lo.xyz + margin, f.box_hi.xyz - margin)) * f.scale.x, kFarAway, f.scale.y);
  }
  return vec3(kFarAway, field_value_at(f, q) * f.scale.x, f.scale.y);
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
    float exit = ray_box_span(origin, inv_dir, node.lo.xyz, node.hi.xyz).y;
    for (uint i = node.first; i < node.first + node.count; ++i) {
      if (count == RTSDF_MAX_NEARBY_FIELDS) return -1;
      nearby_exits[count] = exit;
      nearby_fields[count++] = i;
    }
  }
  return count;
}

// The scene at a world point, over the first `count` gathered fields, as
// field_distance: the smallest bound from the fields whose box the point is
// outside (x) and the smallest clearance from those it is inside (y); and
// the voxel (z) of the field that gives that clearance (or, outside every
// box, of the nearest by bound). The march's epsilon and step cap are in that
// field's voxels: those of the surface nearest the sample. A finer field
// merely nearby (a window frame beside a wall) only bounds the step by how
// far its box is; sizing the steps by its voxels made rays run out of steps
// before they reached the wall, and light came through it.
// Where two fields' surfaces touch (a wall's top under a ceiling slab, a
// modular kit's pieces, a CAD assembly's parts), each reads about 0 at the
// contact, and their minimum there is a hairline of clearance between two
// solids that the solids' union does not have: rays slipped through it, and
// a line of sunlight ran across the interior sample's floor from where its
// walls meet the ceiling (none in Cycles). A point within kContactVoxels
// voxels of two fields' surfaces reads as inside by as much. And inside one
// solid, another's surface no further than the first's (give or take as
// much) means the two touch or overlap there: how deep their union is,
// neither field tells, and the cone, reading one solid's depth, let the
// light through the other. Such points are noted in sampled_contact, and the
// march leaves the share to a ray, as through a sheet.
const float kContactVoxels = 0.25;
bool sampled_contact = false;
// The smallest bound and clearances over the fields sampled so far (nearby_take).
struct Nearby {
  vec3 best;
  float bound_voxel;
  float second, second_voxel;  // the next clearance, another field's
};

Nearby nearby_none() { return Nearby(vec3(kFarAway, kFarAway, 0.0), 0.0, kFarAway, 0.0); }

void nearby_take(inout Nearby n, vec3 d) {
  if (d.x < n.best.x) n.best.x = d.x, n.bound_voxel = d.z;
  if (d.y < n.best.y) n.second = n.best.y, n.second_voxel = n.best.z, n.best.yz = d.yz;
  else if (d.y < n.second) n.second = d.y, n.second_voxel = d.z;
}

vec3 nearby_result(Nearby n) {
  vec3 best = n.best;
  if (best.y >= kFarAway) best.z = n.bound_voxel;
  else if (best.y < kContactVoxels * best.z && n.second < max(-best.y, 0.0) + kContactVoxels * n.second_voxel)
    best.y = min(best.y, -kContactVoxels * best.z), sampled_contact = true;
  return best;
}

vec3 nearby_distance(vec3 world, int count) {
  Nearby n = nearby_none();
  for (int k = 0; k < count; ++k) nearby_take(n, field_distance(nearby_fields[k], world));
  return nearby_result(n);
}

// nearby_distance at the point t along the ray the fields were gathered
// on: a field whose box the ray has left gives nothing more (neither a
// clearance nor a bound worth a step: the ray does not come back), so it is
// not sampled. Where parts lie close together (a CAD assembly, a kit of
// fasteners on a plate), a segment's fields are gathered once and the ray
// passes them one by one.
vec3 nearby_distance_on_ray(vec3 origin, vec3 dir, float t, int count) {
  Nearby n = nearby_none();
  vec3 world = origin + dir * t;
  for (int k = 0; k < count; ++k)
    if (t <= nearby_exits[k]) nearby_take(n, field_distance(nearby_fields[k], world));
  return nearby_result(n);
}
