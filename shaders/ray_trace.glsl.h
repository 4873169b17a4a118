// Closest-hit ray tracing through the two-level BVH (bindings
// RTSDF_RAY_BINDING to RTSDF_RAY_BINDING + 3, from 0 unless the shader says),
// with whether the hit triangle faces the ray (front) or turns its back to it.
#ifndef RTSDF_RAY_BINDING
#define RTSDF_RAY_BINDING 0
#endif
layout(std430, binding = RTSDF_RAY_BINDING) readonly buffer TopNodes { BvhNode top_nodes[]; };
layout(std430, binding = RTSDF_RAY_BINDING + 1) readonly buffer Instances { RayInstance instances[]; };
layout(std430, binding = RTSDF_RAY_BINDING + 2) readonly buffer BottomNodes { BvhNode bottom_nodes[]; };
layout(std430, binding = RTSDF_RAY_BINDING + 3) readonly buffer Triangles { vec4 triangle_corners[]; };  // 3 per triangle

#define RTSDF_STACK 48

#include "ray_box.glsl.h"

// Entry distance of the ray into the box, or a value beyond t_max if it misses.
float box_entry(vec3 origin, vec3 inv_dir, vec4 lo, vec4 hi, float t_max) {
  vec2 span = ray_box_span(origin, inv_dir, lo.xyz, hi.xyz);
  float enter = max(span.x, 0.0);
  return enter <= min(span.y, t_max) ? enter : 3.0e38;
}

// Both children of an inner node are tested where it is reached and the
// nearer taken first, the other kept with its entry distance: a closest hit
// found early then culls the farther boxes without reading them again.
vec2 child_entries(BvhNode left, BvhNode right, vec3 origin, vec3 inv_dir, float best_t) {
  return vec2(box_entry(origin, inv_dir, left.lo, left.hi, best_t), box_entry(origin, inv_dir, right.lo, right.hi, best_t));
}

// any_hit: stop at the first hit within best_t, not the closest (a shadow ray
// only asks whether there is one).
void trace_mesh(uint root, vec3 origin, vec3 dir, bool mirrored, bool any_hit, inout float best_t, inout bool front,
                inout uint best_triangle) {
  vec3 inv_dir = safe_inverse(dir);
  uint stack[RTSDF_STACK];
  float stack_entry[RTSDF_STACK];
  int top = 0;
  BvhNode node = bottom_nodes[root];
  if (box_entry(origin, inv_dir, node.lo, node.hi, best_t) >= best_t) return;
  while (true) {
    if (node.count == 0u) {
      vec2 entry = child_entries(bottom_nodes[node.first], bottom_nodes[node.first + 1u], origin, inv_dir, best_t);
      uint nearer = node.first + (entry.y < entry.x ? 1u : 0u);
      if (min(entry.x, entry.y) < best_t) {
        if (max(entry.x, entry.y) < best_t && top < RTSDF_STACK) {
          stack[top] = (2u * node.first + 1u) - nearer;  // (the other child)
          stack_entry[top++] = max(entry.x, entry.y);
        }
        node = bottom_nodes[nearer];
        continue;
      }
    } else {
      for (uint i = node.first; i < node.first + node.count; ++i) {
        // Moeller-Trumbore; det > 0 when the ray meets the counter-clockwise (front) side.
        vec3 a = triangle_corners[3u * i].xyz;
        vec3 e1 = triangle_corners[3u * i + 1u].xyz - a, e2 = triangle_corners[3u * i + 2u].xyz - a;
        vec3 p = cross(dir, e2);
        float det = dot(e1, p);
        if (abs(det) < 1e-20) continue;
        float inv_det = 1.0 / det;
        vec3 s = origin - a;
        float u = dot(s, p) * inv_det;
        if (u < 0.0 || u > 1.0) continue;
        vec3 q = cross(s, e1);
        float v = dot(dir, q) * inv_det;
        if (v < 0.0 || u + v > 1.0) continue;
        float t = dot(e2, q) * inv_det;
        // (t = 0 counts for a sheet's triangle: a fine texel whose centre lies
        // on a sheet - a flat mesh in the middle of its grid - finds it only so,
        // and read as clear of it. Not for a volume's: where solids touch (a
        // wall under a ceiling) such a face lies inside, and found it reads as a crack.)
        bool counts = t > 0.0 || (t == 0.0 && triangle_corners[3u * i].w == 0.0);
        if (counts && t < best_t) {
          best_t = t;
          front = (det > 0.0) != mirrored;
          best_triangle = i;
          if (any_hit) return;
        }
      }
    }
    // (kept boxes the ray now meets beyond its closest hit are skipped unread)
    while (top > 0 && stack_entry[top - 1] >= best_t) --top;
    if (top == 0) return;
    node = bottom_nodes[stack[--top]];
  }
}

// Returns the closest hit distance below t_max (or t_max), its facing, and
// which triangle (index into triangle_corners / 3) of which instance it hit;
// any_hit: some hit below t_max, not the closest.
float trace_scene(vec3 origin, vec3 dir, float t_max, bool any_hit, out bool front, out uint hit_triangle,
                  out uint hit_instance) {
  front = true;
  hit_triangle = 0u;
  hit_instance = 0u;
  float best_t = t_max;
  // A scene with nothing to hit has a root box inside out (lo above hi). The
  // slab test takes each pair of planes in either order, so it reads such a
  // box as the one between the same planes, and rays through it went on into
  // placeholder buffers: on NVIDIA's driver the traversal never ended.
  if (any(greaterThan(top_nodes[0].lo.xyz, top_nodes[0].hi.xyz))) return best_t;
  // (1 / dir with zeros made huge, not infinite: a zero times infinity is NaN,
  // which drivers order differently in min and max)
  vec3 inv_dir = safe_inverse(dir);
  uint stack[RTSDF_STACK];
  float stack_entry[RTSDF_STACK];
  int top = 0;
  BvhNode node = top_nodes[0];
  if (box_entry(origin, inv_dir, node.lo, node.hi, best_t) >= best_t) return best_t;
  while (true) {
    if (node.count == 0u) {  // (nearer child first, as in trace_mesh)
      vec2 entry = child_entries(top_nodes[node.first], top_nodes[node.first + 1u], origin, inv_dir, best_t);
      uint nearer = node.first + (entry.y < entry.x ? 1u : 0u);
      if (min(entry.x, entry.y) < best_t) {
        if (max(entry.x, entry.y) < best_t && top < RTSDF_STACK) {
          stack[top] = (2u * node.first + 1u) - nearer;
          stack_entry[top++] = max(entry.x, entry.y);
        }
        node = top_nodes[nearer];
        continue;
      }
    } else {
      for (uint i = node.first; i < node.first + node.count; ++i) {
        RayInstance inst = instances[i];
        // Unnormalized object-space direction keeps t in world units.
        vec3 o = (inst.world_to_object * vec4(origin, 1.0)).xyz;
        vec3 d = mat3(inst.world_to_object) * dir;
        float before = best_t;
        trace_mesh(inst.blas_root, o, d, inst.mirrored != 0u, any_hit, best_t, front, hit_triangle);
        if (best_t < before) hit_instance = i;
        if (any_hit && best_t < t_max) return best_t;
      }
    }
    while (top > 0 && stack_entry[top - 1] >= best_t) --top;
    if (top == 0) break;
    node = top_nodes[stack[--top]];
  }
  return best_t;
}

// Distance from p to the triangle (a, b, c) (Ericson, Real-Time Collision
// Detection, 5.1.5: the closest point by Voronoi region).
float point_triangle_distance(vec3 p, vec3 a, vec3 b, vec3 c) {
  vec3 ab = b - a, ac = c - a, ap = p - a;
  float d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return length(ap);
  vec3 bp = p - b;
  float d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return length(bp);
  float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return length(p - (a + ab * (d1 / (d1 - d3))));
  vec3 cp = p - c;
  float d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return length(cp);
  float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return length(p - (a + ac * (d2 / (d2 - d6))));
  float va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
  float denom = 1.0 / (va + vb + vc);
  return length(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

// World thickness of the piece a hit triangle belongs to (0: an open
// surface); the first corner's w holds it in object units (native/mesh_topology.h).
float piece_thickness(uint triangle, uint instance) {
  float scale = pow(abs(determinant(mat3(instances[instance].object_to_world))), 1.0 / 3.0);
  return triangle_corners[3u * triangle].w * scale;
}

// Whether a hit triangle faces into its piece (the piece is inside out, or
// the triangle turned against its neighbours): the second corner's w is -1 then.
bool faces_in(uint triangle) { return triangle_corners[3u * triangle + 1u].w < 0.0; }

// World-space distance from p to a triangle the ray tracer hit, and which
// side of its plane p lies on (`side`): 1 behind it (the side its piece's
// inside is on; faces_in turns that round), -1 in front, 0 for a triangle
// without area.
float distance_to_hit(vec3 p, uint triangle, uint instance, out int side) {
  mat4 m = instances[instance].object_to_world;
  vec3 a = (m * vec4(triangle_corners[3u * triangle].xyz, 1.0)).xyz;
  vec3 b = (m * vec4(triangle_corners[3u * triangle + 1u].xyz, 1.0)).xyz;
  vec3 c = (m * vec4(triangle_corners[3u * triangle + 2u].xyz, 1.0)).xyz;
  vec3 n = cross(b - a, c - a);
  side = dot(n, n) <= 0.0 ? 0 : (dot(p - a, n) < 0.0) != faces_in(triangle) ? 1 : -1;
  return point_triangle_distance(p, a, b, c);
}

float distance_to_hit(vec3 p, uint triangle, uint instance) {
  int side;
  return distance_to_hit(p, triangle, instance, side);
}

// Whether triangle is one of the instance's mesh's (a triangle index kept
// from an earlier frame may not be, once the scene's meshes changed).
bool is_triangle_of(uint triangle, uint instance) {
  return instance < uint(instances.length()) && triangle - instances[instance].first_triangle < instances[instance].triangle_count;
}
