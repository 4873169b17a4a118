// The packed field's bricks (kBrickTexels in shared.h) over a fine grid of
// `dims` texels, counted as bricks_of in native/grid.cpp does, and what the
// fine SDF's steps keep per brick (fine_bricks_near.comp).
ivec3 bricks_of(ivec3 dims) { return max(dims - 2, ivec3(0)) / int(kBrickCells) + 1; }

uint brick_index(ivec3 brick, ivec3 bricks) { return uint(brick.x + bricks.x * (brick.y + bricks.y * brick.z)); }

// The coarse texels [lo, hi] whose values the coarse SDF's trilinear
// samples at the centres of fine texels [first, last] read. A brick is near
// the band where one of them is in it: a trilinear sample is never below
// all its corners.
void coarse_footprint(ivec3 first, ivec3 last, vec4 fine_grid, vec4 coarse_grid, ivec3 coarse_dims, out ivec3 lo,
                      out ivec3 hi) {
  vec3 a = (fine_grid.xyz + (vec3(first) + 0.5) * fine_grid.w - coarse_grid.xyz) / coarse_grid.w - 0.5;
  vec3 b = (fine_grid.xyz + (vec3(last) + 0.5) * fine_grid.w - coarse_grid.xyz) / coarse_grid.w - 0.5;
  lo = clamp(ivec3(floor(a)), ivec3(0), coarse_dims - 1);
  hi = clamp(ivec3(floor(b)) + 1, ivec3(0), coarse_dims - 1);
}

const uint kBrickNearNow = 1u;     // near the band in this update
const uint kBrickNearBefore = 2u;  // near it in the update before: its texels hold the field's history
