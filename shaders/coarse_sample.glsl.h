// Trilinear sample of the coarse SDF (image `coarse`) at a world position;
// needs pc.coarse_dims and pc.coarse_grid.
float sample_coarse(vec3 world) {
  vec3 q = (world - pc.coarse_grid.xyz) / pc.coarse_grid.w - 0.5;
  ivec3 hi_index = pc.coarse_dims.xyz - 1;
  vec3 base = floor(q);
  vec3 f = clamp(q - base, 0.0, 1.0);
  ivec3 i0 = clamp(ivec3(base), ivec3(0), hi_index);
  ivec3 i1 = clamp(ivec3(base) + 1, ivec3(0), hi_index);
  float c000 = imageLoad(coarse, ivec3(i0.x, i0.y, i0.z)).x, c100 = imageLoad(coarse, ivec3(i1.x, i0.y, i0.z)).x;
  float c010 = imageLoad(coarse, ivec3(i0.x, i1.y, i0.z)).x, c110 = imageLoad(coarse, ivec3(i1.x, i1.y, i0.z)).x;
  float c001 = imageLoad(coarse, ivec3(i0.x, i0.y, i1.z)).x, c101 = imageLoad(coarse, ivec3(i1.x, i0.y, i1.z)).x;
  float c011 = imageLoad(coarse, ivec3(i0.x, i1.y, i1.z)).x, c111 = imageLoad(coarse, ivec3(i1.x, i1.y, i1.z)).x;
  return mix(mix(mix(c000, c100, f.x), mix(c010, c110, f.x), f.y), mix(mix(c001, c101, f.x), mix(c011, c111, f.x), f.y), f.z);
}
