// A fine texel's history (rgba32f, fine_trace.comp):
//   x: 1 while its traces still find closer surfaces (the classify step of a
//      still field lists only those), plus 2 if its last trace put it inside,
//      plus 4 times the instance of its kept triangle;
//   y: its kept triangle + 1 (0: none), the nearest one its traces found;
//   z: f, w: g (the distances fine_trace.comp updates).
// Indices are whole numbers in floats, exact below 2^24; larger ones are not kept.
const uint kNoTriangle = 0xffffffffu;
const uint kMaxExactTriangle = (1u << 24) - 1u, kMaxExactInstance = (1u << 22) - 1u;

vec4 make_history(bool improving, bool inside, uint triangle, uint instance, float f, float g) {
  bool kept = triangle < kMaxExactTriangle && instance <= kMaxExactInstance;
  uint flags = (improving ? 1u : 0u) + (inside ? 2u : 0u);
  return vec4(float(flags + (kept ? 4u * instance : 0u)), kept ? float(triangle + 1u) : 0.0, f, g);
}

bool history_improving(vec4 history) { return (uint(history.x) & 1u) != 0u; }
bool history_inside(vec4 history) { return (uint(history.x) & 2u) != 0u; }

// The kept triangle and its instance, or false.
bool history_kept_triangle(vec4 history, out uint triangle, out uint instance) {
  triangle = uint(history.y) - 1u;
  instance = uint(history.x) >> 2;
  return history.y > 0.0;
}
