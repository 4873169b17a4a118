#version 450
#extension GL_GOOGLE_include_directive : require
// Voxelization, vertex stage: each triangle is projected along its dominant axis
// (+x, +y or +z) and grown so that every pixel it touches is rasterized, since
// lavapipe has no conservative rasterization.
#include "shared.h"
#include "voxel_common.glsl.h"

layout(location = 0) flat out uint v_axis;
layout(location = 1) flat out vec4 v_clip_rect;  // pixel centres outside this rect miss the triangle

void main() {
  uint triangle = uint(gl_VertexIndex) / 3u;
  uint corner = uint(gl_VertexIndex) % 3u;
  vec3 p0 = triangle_corner(triangle, 0u);
  vec3 p1 = triangle_corner(triangle, 1u);
  vec3 p2 = triangle_corner(triangle, 2u);
  if (splat_sized(p0, p1, p2)) {  // marked by voxelize_splat.comp instead
    gl_Position = vec4(-2.0, -2.0, 0.5, 1.0);
    v_axis = 0u;
    v_clip_rect = vec4(0.0);
    return;
  }
  uint axis = dominant_axis(cross(p1 - p0, p2 - p0));
  vec2 q[3] = vec2[3](to_view(p0, axis).xy, to_view(p1, axis).xy, to_view(p2, axis).xy);

  // A pixel overlaps the triangle's box iff its centre lies in the box grown by
  // half a pixel (and a hair, so that touching survives rounding).
  vec2 lo = min(min(q[0], q[1]), q[2]) - 0.501;
  vec2 hi = max(max(q[0], q[1]), q[2]) + 0.501;
  v_clip_rect = vec4(lo, hi) + vec4(float(axis * uint(pc.dims.w)), 0.0, float(axis * uint(pc.dims.w)), 0.0);
  v_axis = axis;

  float twice_area = (q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (q[1].y - q[0].y);
  vec2 out_pos;
  if (abs(twice_area) < 1e-7) {
    // Degenerate (a segment or a point): cover its grown bounding box with one big triangle.
    vec2 size = hi - lo;
    out_pos = corner == 0u ? lo : (corner == 1u ? vec2(lo.x + 2.0 * size.x, lo.y) : vec2(lo.x, lo.y + 2.0 * size.y));
  } else {
    // Move every edge outward by half a pixel diagonal (in the max norm) and
    // intersect neighbouring edges (GPU Gems 2, ch. 42). Spikes at sharp corners
    // are trimmed by v_clip_rect in the fragment stage.
    float orientation = twice_area > 0.0 ? 1.0 : -1.0;
    vec3 edge[3];
    for (int i = 0; i < 3; ++i) {
      vec3 line = orientation * cross(vec3(q[i], 1.0), vec3(q[(i + 1) % 3], 1.0));
      // A little more than half a pixel: vertices snap to 1/256 pixel when rasterized.
      line.z += 0.51 * (abs(line.x) + abs(line.y));
      edge[i] = line;
    }
    vec3 h = cross(edge[(corner + 2u) % 3u], edge[corner]);
    out_pos = h.xy / h.z;
  }
  // The three projections sit side by side (x offset axis * edge): llvmpipe
  // rasterizes 64x64-pixel tiles in parallel, so more tiles means more threads.
  float edge = float(pc.dims.w);
  out_pos.x += float(axis) * edge;
  gl_Position = vec4(out_pos / vec2(3.0 * edge, edge) * 2.0 - 1.0, 0.5, 1.0);
}
