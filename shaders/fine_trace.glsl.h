// Fine SDF, step 3 (fine_trace.comp; fine_remeasure.comp, with
// RTSDF_REMEASURE defined, for the texels off their turn in a field whose
// geometry changes, which cast no ray): each listed texel casts rays_per_texel rays (a spherical
// Fibonacci set turned by a new rotation every frame) and measures the
// distance from its centre to every triangle they hit. The paper keeps the
// smallest of them over frames as a value that decays towards the coarse
// SDF's, f_t = min(alpha * f_{t-1} + (1 - alpha) * c_t, r_t), so that a
// surface that moved away is forgotten, slowly. Here each texel keeps the
// triangle instead (the nearest any of its traces hit, fine_history.glsl.h)
// and measures it again every trace, in this frame's shape and place, with
// its six neighbours' kept triangles (in fields whose geometry changes):
//   f_t = min(c_t + bias, distances to the kept triangles, r_t).
// Every term is an upper bound of the texel's distance in this frame, so a
// surface that moved away leaves nothing stale behind; the neighbours'
// triangles spread each surface found over the band as a jump flood
// spreads seeds, and a deforming mesh's texels carry their nearest surface
// from frame to frame without a traversal (a ray costs about as much
// however short; a distance to one triangle next to nothing), so such
// meshes trace one ray a texel and frame. Kept triangles give no vote on
// the sign: which side of one the texel is on says nothing of the inside
// unless no other surface lies between them, and only a ray can tell that.
// The texel is inside (negative) where the generalized winding number of the
// meshes' volumes says so (winding_number.glsl.h): it holds on cracked,
// overlapping and inside-out parts, and it depends on the geometry alone, so
// a moved object leaves no inside behind. Summing solid angles costs as much
// as all the rays, so it is taken only where the rays leave the sign in
// doubt. Where every ray that met a volume met it from the same side (its
// back faces: inside; front faces: outside; an inside-out piece's the other
// way round), the winding number can only agree, and that vote is taken,
// unless it contradicts the sign the texel's last trace found (its history):
// then the surface may have crossed the texel, or one ray may have slipped
// through a crack, and the winding number decides. A texel that was inside
// and whose rays met no volume is decided by it too. With one ray a frame,
// a texel's votes so add up over frames while its surface stays where it is.
// (A texel off its turn has no votes: it doubts its sign where it changed
// sides of its nearest kept triangle's plane, below. Doubted texels are
// listed, and fine_signs.comp takes their winding numbers.)
// Sheets have no inside, and a closed piece thinner than a voxel has no
// texel inside it, so marches through it would never see a negative value
// (its shadow would be half lit). Such thin pieces are kept apart: the
// distance g to their slabs, updated as the paper updates f (from rays
// alone: a slab a kept triangle held in place every frame speckled the faces
// beside thin parts), and the stored value is min(+-f, g). A closed thin
// piece reads as a slab half a voxel thick on either side, a sheet (no
// thickness at all) a whole voxel: a march crossing it must see a value well
// below zero to be blocked, and each half voxel of slab widens the piece's
// shadow by as much.
// Texels whose rays found a surface closer (by a quarter voxel) than their
// value are still improving (history.x, which the classify step of a still
// field reads) and, in a still field, are counted: once none is, the field
// has converged.
#include "shared.h"
#include "seed_common.glsl.h"  // texel indices are packed like seeds
#include "fine_history.glsl.h"

layout(local_size_x = RTSDF_TRACE_GROUP) in;
#include "ray_trace.glsl.h"
layout(binding = 4, r32f) uniform readonly image3D coarse;
layout(binding = 5, r32f) uniform image3D fine;
layout(binding = 6, rgba32f) uniform image3D history;  // fine_history.glsl.h
layout(std430, binding = 7) readonly buffer TraceList { uint trace_count; uint remeasure_count; uint trace_texels[]; };  // fine_classify.comp
#define RTSDF_WINDING_BINDING 8
#include "winding_number.glsl.h"
layout(std430, binding = 9) buffer Dispatch { uvec4 groups; uint improved; };
layout(std430, binding = 10) buffer Doubts { uint doubt_count; uint doubt_groups[3]; uint doubt_texels[]; };  // fine_signs.comp
// fine_trace.comp: the texels on their turn, which cast rays.
// fine_remeasure.comp: those measured again off their turn (from the back
// of the list), in a dispatch of its own without the rays' traversal: in
// one list, most SIMD groups held a texel on its turn, and on lavapipe all
// their lanes ran its traversal (a deforming character's fine update 45 ms
// a frame, against 40 ms apart).
// fine_probe.comp: after a still field's first update, the texels it
// traced, which cast no ray but find whether they may improve (below).
#ifdef RTSDF_REMEASURE
const bool on_turn = false;
#else
const bool on_turn = true;
#endif
layout(push_constant) uniform Push { FinePush pc; };

#include "coarse_sample.glsl.h"

vec3 rotate(vec4 q, vec3 v) { return v + 2.0 * cross(q.xyz, cross(q.xyz, v) + q.w * v); }

float slab_half_thickness(float thickness) { return (thickness > 0.0 ? 0.5 : 1.0) * pc.fine_grid.w; }

// What this texel's hits found: the nearest distance to any surface and to
// a thin piece's slab, the votes of volumes at least a voxel thick (from
// outside, from inside), and the nearest triangle.
float nearest, nearest_slab;
vec2 hits;
uint nearest_triangle, nearest_instance;
int nearest_side;  // which side of the nearest triangle's plane the texel is on (distance_to_hit)

// A triangle at distance from the texel, the texel on `side` of its plane;
// by_ray: a ray met it (from the front or not).
void take_hit(uint triangle, uint instance, float distance, int side, bool by_ray, bool front) {
  if (distance < nearest) nearest = distance, nearest_triangle = triangle, nearest_instance = instance, nearest_side = side;
  if (!by_ray) return;
  float thickness = piece_thickness(triangle, instance);
  if (thickness < pc.fine_grid.w)
    nearest_slab = min(nearest_slab, distance - slab_half_thickness(thickness));
  else
    hits += front != faces_in(triangle) ? vec2(1.0, 0.0) : vec2(0.0, 1.0);
}

// A kept triangle (the texel's own or a neighbour's), measured in this frame's shape.
void take_kept(vec3 world, uint triangle, uint instance) {
  int side;
  float distance = distance_to_hit(world, triangle, instance, side);
  if (distance < pc.params.w) take_hit(triangle, instance, distance, side, false, false);
}

// Lists texel p for the sign step (fine_signs.comp), counting its work
// groups as they fill; false where the list is full.
bool doubt(ivec3 p) {
  uint slot = atomicAdd(doubt_count, 1u);
  if (slot >= uint(doubt_texels.length())) return false;
  doubt_texels[slot] = pack_seed(p);
  if (slot % uint(RTSDF_TRACE_GROUP) == 0u) atomicAdd(doubt_groups[0], 1u);
  return true;
}

void main() {
  uint item = gl_GlobalInvocationID.x;
  if (item >= (on_turn ? trace_count : remeasure_count)) return;
  ivec3 p = unpack_seed(trace_texels[on_turn ? item : uint(trace_texels.length()) - 1u - item]);
  vec3 world = pc.fine_grid.xyz + (vec3(p) + 0.5) * pc.fine_grid.w;
  float c = sample_coarse(world);

  bool first_frame = pc.coarse_dims.w != 0;
  bool still = (uint(pc.state.y) & kFineStill) != 0u;  // (only a still field's convergence is counted)
  float alpha = pc.params.x;
  float target = max(c + pc.params.z, 0.0);  // (params.z: the bias that makes it an upper bound)
#ifdef RTSDF_PROBE
  vec4 previous = imageLoad(history, p);  // (what the first update wrote)
#else
  vec4 previous = first_frame ? vec4(0.0, 0.0, target, pc.params.w) : imageLoad(history, p);
#endif

  nearest = pc.params.w, nearest_slab = pc.params.w;
  hits = vec2(0.0);
  nearest_triangle = kNoTriangle, nearest_instance = 0u, nearest_side = 0;
  uint kept, kept_instance;
  bool known = history_kept_triangle(previous, kept, kept_instance) && is_triangle_of(kept, kept_instance);
  if (known) take_kept(world, kept, kept_instance);
  // Where the geometry changes from update to update (not a still field),
  // the six neighbours' kept triangles too: a nearest surface one texel
  // found spreads to the others, one texel a trace, as in a jump flood.
  // (A neighbour may be written by this pass as it is read: any triangle
  // of its instance's mesh is a surface, and so an upper bound.) A still
  // field's own rays converge over its updates; there the neighbours' made
  // it tighter than the march's thin-piece slabs are tuned to (bench/run
  // --quick at Preview: interior 0.0131 -> 0.0150, tree 0.0662 -> 0.0687).
  // (Neighbours mostly keep the same few triangles: each is measured once.)
#ifdef RTSDF_PROBE
  const bool measure_neighbours = true;
#else
  bool measure_neighbours = !first_frame && !still;
#endif
  if (measure_neighbours) {
    uvec2 measured[7];
    int count = 0;
    if (known) measured[count++] = uvec2(kept, kept_instance);
    for (int k = 0; k < 6; ++k) {
      ivec3 q = p;
      q[k >> 1] += (k & 1) == 0 ? -1 : 1;
      uint triangle, instance;
      if (any(lessThan(q, ivec3(0))) || any(greaterThanEqual(q, pc.fine_dims.xyz)) ||
          !history_kept_triangle(imageLoad(history, q), triangle, instance))
        continue;
      bool seen = false;
      for (int i = 0; i < count; ++i) seen = seen || measured[i] == uvec2(triangle, instance);
      if (seen || !is_triangle_of(triangle, instance)) continue;
      measured[count++] = uvec2(triangle, instance);
      take_kept(world, triangle, instance);
    }
  }

#ifdef RTSDF_PROBE
  // A still field's first rays found each texel's nearest surface, but for
  // the texels whose rays all missed a closer one (8-12% of them on the
  // bolts and the CAD engine). A neighbour's kept triangle closer than the
  // texel's own is such a miss, and a texel with no triangle may be one.
  // A texel whose rays met a thin piece (its slab g below the ray length)
  // stays too: the paper's decaying update moves the slab every trace, and
  // the march's slabs are tuned to it (without this the Preview row lost
  // on leaf cards and thin parts). Only those stay listed for the next
  // update's rays (the rest would find nothing, and cost as much as the
  // first update). Their value and sign stay as they are (the neighbours'
  // triangles are only a doubt).
  bool may_improve = !known || nearest < previous.z - 0.25 * pc.fine_grid.w || previous.w < pc.params.w;
  imageStore(history, p, vec4(float((uint(previous.x) & ~1u) | (may_improve ? 1u : 0u)), previous.yzw));
  return;
#endif

#if !defined(RTSDF_REMEASURE) && !defined(RTSDF_PROBE)
  const int rays = pc.fine_dims.w;
  const float golden_angle = 2.39996323;
  for (int i = 0; i < rays; ++i) {
    float z = 1.0 - (2.0 * float(i) + 1.0) / float(rays);
    float r = sqrt(max(0.0, 1.0 - z * z));
    float phi = golden_angle * float(i);
    vec3 dir = rotate(pc.rotation, vec3(r * cos(phi), r * sin(phi), z));
    bool front;
    uint triangle, instance;
    float t = trace_scene(world, dir, pc.params.w, false, front, triangle, instance);
    // The exact distance to the triangle hit is still an upper bound of the
    // texel's distance, and no larger than t: minima converge much faster.
    int side;
    if (t < pc.params.w) take_hit(triangle, instance, min(t, distance_to_hit(world, triangle, instance, side)), side, true, front);
  }
#endif

  bool unanimous = hits.x == 0.0 || hits.y == 0.0, voted_inside = hits.y > 0.0;
  bool was_inside = history_inside(previous);
  bool settled = unanimous && (!known || (hits == vec2(0.0) ? !was_inside : voted_inside == was_inside));
  // Off its turn, a texel keeps its sign unless the side of the plane of
  // its nearest kept triangle (of a volume) says otherwise: the surface may
  // have crossed it (or the plane's side is wrong there, past an edge).
  // Not where the surface lies farther from it than any point of the
  // surface moved since the last update (pc.state.z; half a voxel more for
  // the kept triangles' error): it has not crossed the texel, and the side
  // is no news. (Most doubts are the plane's: of a deforming character's
  // 300-1,500 doubted texels an update, the winding number kept 75-95% on
  // the side they were; this leaves out about half of them.)
  if (!on_turn) {
    bool volume = nearest_side != 0 && piece_thickness(nearest_triangle, nearest_instance) >= pc.fine_grid.w;
    bool within_reach = nearest <= pc.state.z + 0.5 * pc.fine_grid.w;
    settled = !volume || !within_reach || (nearest_side > 0) == was_inside;
    voted_inside = was_inside;
  }
  // A doubted sign is the winding number's, taken by the sign step (here
  // only where its list is full); meanwhile the texel keeps its last.
  bool inside = settled ? voted_inside : doubt(p) ? was_inside : inside_scene(world);
  // (a quarter voxel closer to a surface, or to a thin piece's slab)
  bool improving = first_frame || min(nearest - previous.z, nearest_slab - previous.w) < -0.25 * pc.fine_grid.w;
  if (improving && !first_frame && still) atomicAdd(improved, 1u);
  float f = min(target, nearest);
  float g = on_turn ? min(alpha * previous.w + (1.0 - alpha) * pc.params.w, nearest_slab) : previous.w;
  imageStore(history, p, make_history(improving, inside, nearest_triangle, nearest_instance, f, g));
  imageStore(fine, p, vec4(min(inside ? -f : f, g)));
}
