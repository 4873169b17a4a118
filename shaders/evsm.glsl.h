// Exponential variance shadow maps (Lauritzen): a depth d in [0, 1] is mapped
// to x = 2d - 1 and warped twice, e^(c+ x) and -e^(-c- x); a map stores each
// warp and its square. Both warps grow with depth.
vec2 evsm_warp(float depth, vec2 exponents) {
  float x = 2.0 * clamp(depth, 0.0, 1.0) - 1.0;
  return vec2(exp(exponents.x * x), -exp(-exponents.y * x));
}

// Chebyshev's upper bound on the share of the filtered texels at least as far
// from the light as `receiver` (the share of light reaching it), from the
// moments (mean, mean of squares) of one warp.
float chebyshev_upper_bound(vec2 moments, float receiver, float min_variance) {
  if (receiver <= moments.x) return 1.0;
  float variance = max(moments.y - moments.x * moments.x, min_variance);
  float d = receiver - moments.x;
  return variance / (variance + d * d);
}
