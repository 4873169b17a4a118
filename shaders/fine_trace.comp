#version 450
#extension GL_GOOGLE_include_directive : require
// Fine SDF, step 3: each listed texel casts rays_per_texel rays (a spherical
// Fibonacci set turned by a new rotation every frame) and updates
//   f_t = min(alpha * f_{t-1} + (1 - alpha) * (c_t + bias), r_t)
// with r_t the smallest distance from the texel to a triangle a ray hit. The
// texel is inside (negative) when back faces outnumber front faces (see the
// sign below).
// Back faces mean "inside" only on closed surfaces: behind a one-sided sheet
// they would mark the whole band as inside, and shadows would spread from it;
// and a closed piece thinner than a voxel has no texel inside it, so marches
// through it never see a negative value (its shadow would be half lit).
// Hits on such thin pieces are not counted; instead the distance g to their
// slabs is kept apart (updated like f) and the stored value is min(+-f, g).
// A closed thin piece reads as a slab half a voxel thick on either side, an
// open one (no thickness at all) a whole voxel: a march crossing it must see
// a value well below zero to be blocked, and each half voxel of slab widens
// the piece's shadow by as much.
#include "shared.h"
#include "seed_common.glsl.h"  // texel indices are packed like seeds

layout(local_size_x = RTSDF_TRACE_GROUP) in;
#include "ray_trace.glsl.h"
layout(binding = 4, r32f) uniform readonly image3D coarse;
layout(binding = 5, r32f) uniform image3D fine;
layout(binding = 6, rgba32f) uniform image3D hit_counts;  // front and back counts, f, g
layout(std430, binding = 7) readonly buffer TraceList { uint trace_count; uint trace_texels[]; };
layout(push_constant) uniform Push { FinePush pc; };

#include "coarse_sample.glsl.h"

vec3 rotate(vec4 q, vec3 v) { return v + 2.0 * cross(q.xyz, cross(q.xyz, v) + q.w * v); }

float slab_half_thickness(float thickness) { return (thickness > 0.0 ? 0.5 : 1.0) * pc.fine_grid.w; }

void main() {
  uint item = gl_GlobalInvocationID.x;
  if (item >= trace_count) return;
  ivec3 p = unpack_seed(trace_texels[item]);
  vec3 world = pc.fine_grid.xyz + (vec3(p) + 0.5) * pc.fine_grid.w;
  float c = sample_coarse(world);

  const int rays = pc.fine_dims.w;
  const float golden_angle = 2.39996323;
  // nearest_slab: distance to the nearest thin piece's slab (negative inside it).
  float nearest = pc.params.w, nearest_slab = pc.params.w;
  vec2 hits = vec2(0.0);  // front, back (closed surfaces only)
  for (int i = 0; i < rays; ++i) {
    float z = 1.0 - (2.0 * float(i) + 1.0) / float(rays);
    float r = sqrt(max(0.0, 1.0 - z * z));
    float phi = golden_angle * float(i);
    vec3 dir = rotate(pc.rotation, vec3(r * cos(phi), r * sin(phi), z));
    bool front;
    uint triangle, instance;
    float t = trace_scene(world, dir, pc.params.w, front, triangle, instance);
    if (t < pc.params.w) {
      // The exact distance to the triangle hit is still an upper bound of the
      // texel's distance, and no larger than t: minima converge much faster.
      float distance = min(t, distance_to_hit(world, triangle, instance));
      nearest = min(nearest, distance);
      float thickness = piece_thickness(triangle, instance);
      if (thickness < pc.fine_grid.w)
        nearest_slab = min(nearest_slab, distance - slab_half_thickness(thickness));
      else
        hits += front ? vec2(1.0, 0.0) : vec2(0.0, 1.0);
    }
  }

  bool first_frame = pc.coarse_dims.w != 0;
  float alpha = pc.params.x;
  float target = max(c + pc.params.z, 0.0);  // params.z = 0: the paper's c_t
  vec4 history = first_frame ? vec4(0.0, 0.0, target, pc.params.w) : imageLoad(hit_counts, p);
  // The sign. From outside a closed surface a ray meets a front face first,
  // from inside a back face: on clean meshes every frame's hits agree, and
  // they are taken as they are (no rays met one: outside). Remembered counts
  // would keep a moved object's inside where it was for many frames - its
  // ghost. Only where hits disagree (overlapping or self-intersecting
  // pieces) does the decayed history vote along.
  bool unanimous = hits.x == 0.0 || hits.y == 0.0;
  vec2 counts = (unanimous ? vec2(0.0) : alpha * history.xy) + hits;
  float f = min(alpha * history.z + (1.0 - alpha) * target, nearest);
  float g = min(alpha * history.w + (1.0 - alpha) * pc.params.w, nearest_slab);
  imageStore(hit_counts, p, vec4(counts, f, g));
  imageStore(fine, p, vec4(min(counts.y > counts.x ? -f : f, g)));
}
