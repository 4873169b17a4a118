// The packed field's bricks (kBrickTexels in shared.h) over a fine grid of
// `dims` texels, counted as bricks_of in native/grid.cpp does, and what the
// fine SDF's steps keep per brick (fine_bricks_near.comp).
ivec3 bricks_of(ivec3 dims) { return max(dims - 2, ivec3(0)) / int(kBrickCells) + 1; }

uint brick_index(ivec3 brick, ivec3 bricks) { return uint(brick.x + bricks.x * (brick.y + bricks.y * brick.z)); }
ivec3 brick_at(uint index, ivec3 bricks) {
  return ivec3(int(index) % bricks.x, (int(index) / bricks.x) % bricks.y, int(index) / (bricks.x * bricks.y));
}

const uint kBrickNearNow = 1u;     // near the band in this update
const uint kBrickNearBefore = 2u;  // near it in the update before: its texels hold the field's history
