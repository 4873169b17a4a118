#version 450
#extension GL_GOOGLE_include_directive : require
// The exact Euclidean distance transform of the seeds (Felzenszwalb and
// Huttenlocher, "Distance Transforms of Sampled Functions", 2012): three
// passes, one per axis, each taking every line of the grid along its axis
// (an invocation per line) from the squared distances of the pass before to
// the lower envelope of the parabolas they root, in O(n) a line. The first
// pass reads the seeds themselves (0 at a seed, none elsewhere), the last
// writes the coarse SDF: |voxel centre - nearest seed centre| * voxel size
// - beta, as the jump flood's seed_distance.comp does, but exact (the flood
// misses the nearest seed now and then) and with 3 reads and writes a voxel
// instead of the flood's 27 reads in each of its log2(N) + 1 passes.
#include "shared.h"
#include "seed_common.glsl.h"

layout(local_size_x = 64) in;
layout(binding = 0, r32ui) uniform readonly uimage3D squared_in;   // the seeds, in the first pass
layout(binding = 1, r32ui) uniform writeonly uimage3D squared_out;  // (not the last pass's)
layout(binding = 2, r32f) uniform writeonly image3D distance_out;   // (the last pass's)
layout(push_constant) uniform Push { SeedDistancePush pc; };  // (scale: the last pass's)
layout(constant_id = 0) const int kAxis = 0;  // 0: the first pass (x), 2: the last (z)
// The longest line the pipeline takes (a power of two, up to 1 << kSeedBits):
// each invocation holds three arrays of it in private memory, which GPUs
// reserve for every invocation that may run at once, so the pipeline is
// sized to the grid (ExactDistancePass picks it).
layout(constant_id = 1) const int kMaxLine = 1 << kSeedBits;

const uint kNone = 0xFFFFFFFFu;  // no seed on the line yet, or anywhere (squared distances are far below)

// The voxel at `along` on the line.
ivec3 voxel(ivec3 line_start, int along) {
  ivec3 p = line_start;
  p[kAxis] = along;
  return p;
}

uint squared_at(ivec3 p) {
  uint s = imageLoad(squared_in, p).x;
  if (kAxis == 0) return s == kNoSeed ? kNone : 0u;  // (the seeds: a voxel's own)
  return s;
}

void main() {
  ivec3 dims = pc.dims.xyz;
  // The line: the other two axes' coordinates from the invocation index.
  int across0 = (kAxis + 1) % 3, across1 = (kAxis + 2) % 3;
  int line = int(gl_GlobalInvocationID.x);
  if (line >= dims[across0] * dims[across1]) return;
  ivec3 start = ivec3(0);
  start[across0] = line % dims[across0];
  start[across1] = line / dims[across0];
  int n = dims[kAxis];

  // The lower envelope: the parabolas' roots (vertex) and squared heights
  // (f), and where each takes over from the one before (boundary).
  int vertex[kMaxLine];
  uint height[kMaxLine];
  float boundary[kMaxLine + 1];
  int k = -1;
  for (int q = 0; q < n; ++q) {
    uint f = squared_at(voxel(start, q));
    if (f == kNone) continue;
    float s = -3.0e38;
    while (k >= 0) {
      // Where parabola q meets the envelope's last one.
      int v = vertex[k];
      s = (float(int(f) + q * q) - float(int(height[k]) + v * v)) / float(2 * (q - v));
      if (s > boundary[k]) break;
      --k;
    }
    if (k < 0) s = -3.0e38;
    ++k;
    vertex[k] = q;
    height[k] = f;
    boundary[k] = s;
  }

  int j = 0;
  for (int q = 0; q < n; ++q) {
    uint squared = kNone;
    if (k >= 0) {
      while (j < k && boundary[j + 1] <= float(q)) ++j;
      int d = q - vertex[j];
      squared = height[j] + uint(d * d);
    }
    ivec3 p = voxel(start, q);
    if (kAxis < 2) {
      imageStore(squared_out, p, uvec4(squared));
    } else {
      // No seed anywhere (an empty grid) reads as far away, as in the flood.
      float voxels = squared == kNone ? float(dims.x + dims.y + dims.z) : sqrt(float(squared));
      imageStore(distance_out, p, vec4(voxels * pc.scale.x - pc.scale.y));
    }
  }
}
