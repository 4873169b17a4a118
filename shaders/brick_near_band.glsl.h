// Whether a brick whose texels are [first, last] is near the trace band:
// a coarse texel that the trilinear coarse samples at their centres read
// is at most `band` from a surface (a trilinear sample is never below all
// its corners). The fine SDF classifies such bricks (fine_bricks_near.comp)
// and the packer stores them (field_brick_slots.comp). Needs the coarse
// SDF's image `coarse` and a push constant `pc` with fine_grid, coarse_grid
// and coarse_dims.
bool brick_near_band(ivec3 first, ivec3 last, float band) {
  vec3 a = (pc.fine_grid.xyz + (vec3(first) + 0.5) * pc.fine_grid.w - pc.coarse_grid.xyz) / pc.coarse_grid.w - 0.5;
  vec3 b = (pc.fine_grid.xyz + (vec3(last) + 0.5) * pc.fine_grid.w - pc.coarse_grid.xyz) / pc.coarse_grid.w - 0.5;
  ivec3 top = pc.coarse_dims.xyz - 1;
  ivec3 lo = clamp(ivec3(floor(a)), ivec3(0), top), hi = clamp(ivec3(floor(b)) + 1, ivec3(0), top);
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x)
        if (imageLoad(coarse, ivec3(x, y, z)).x <= band) return true;
  return false;
}
