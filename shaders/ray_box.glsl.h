#ifndef RTSDF_RAY_BOX_GLSL_H
#define RTSDF_RAY_BOX_GLSL_H
// Where a ray (origin + t dir, inv_dir = 1 / dir) is inside an axis-aligned
// box: (t entering, t leaving); it misses the box when x > y.
vec2 ray_box_span(vec3 origin, vec3 inv_dir, vec3 lo, vec3 hi) {
  vec3 t0 = (lo - origin) * inv_dir, t1 = (hi - origin) * inv_dir;
  vec3 near = min(t0, t1), far = max(t0, t1);
  return vec2(max(max(near.x, near.y), near.z), min(min(far.x, far.y), far.z));
}

// 1 / dir with zero components replaced by a huge value of the same use.
vec3 safe_inverse(vec3 dir) { return 1.0 / mix(dir, vec3(1e-20), equal(dir, vec3(0.0))); }
#endif
