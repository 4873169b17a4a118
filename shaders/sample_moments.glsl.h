// The running second moments of a pixel's samples, beside their running
// means (the accumulation): the Y, Co and Cg of the Combined colour,
// squared (w, no mean: the instances its samples saw, their bits as a
// whole number, see shared.h's kHistoryBits). Their spread is the pixel's
// own noise, known after its samples, where one frame's neighbourhood can
// only guess it: the world light's few cones give near-discrete values, and
// a few neighbours' often agree exactly, while the samples of one pixel over
// frames do not.
vec3 to_ycocg(vec3 c) {
  return vec3(0.25 * c.r + 0.5 * c.g + 0.25 * c.b, 0.5 * c.r - 0.5 * c.b, -0.25 * c.r + 0.5 * c.g - 0.25 * c.b);
}
vec3 from_ycocg(vec3 c) { return vec3(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z); }

// A sample's contribution to the second moments.
vec4 sample_moments(vec3 color) {
  vec3 y = to_ycocg(color);
  return vec4(y * y, 0.0);
}

// One sample's standard deviation (YCoCg) from the running mean `color` and
// second moments of a pixel's samples.
vec3 sample_sigma(vec4 moments, vec3 color) {
  vec3 y = to_ycocg(color);
  return sqrt(max(moments.xyz - y * y, 0.0));
}

// Second moments for a mean moved (clipped) from `mean` to `moved`: the
// samples' spread stays, around the new mean.
vec4 moments_moved_to(vec4 moments, vec3 mean, vec3 moved) {
  vec3 sigma = sample_sigma(moments, mean), y = to_ycocg(moved);
  return vec4(y * y + sigma * sigma, 0.0);
}

#ifndef RTSDF_NO_GBUFFER
// The history bit of the instance a G-buffer pixel shows (none where it
// shows no surface). Needs g_normal (its w holds the bit).
uint surface_bits(ivec2 pixel, vec4 position) {
  return position.w > 0.0 ? 1u << uint(imageLoad(g_normal, pixel).w) : 0u;
}
#endif
