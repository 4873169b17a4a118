// A fine texel's history (rgba32f, fine_trace.comp):
//   x: 1 while its traces still find closer surfaces (the classify step of a
//      still field lists only those), plus twice the instance of its kept triangle;
//   y: its kept triangle + 1 (0: none), the nearest one its traces found;
//   z: f, w: g (the distances fine_trace.comp updates).
// Indices are whole numbers in floats, exact below 2^24; larger ones are not kept.
const uint kNoTriangle = 0xffffffffu;
const uint kMaxExactIndex = 1u << 23;

vec4 make_history(bool improving, uint triangle, uint instance, float f, float g) {
  bool kept = triangle < 2u * kMaxExactIndex && instance < kMaxExactIndex;
  return vec4(float((kept ? 2u * instance : 0u) + (improving ? 1u : 0u)), kept ? float(triangle + 1u) : 0.0, f, g);
}

bool history_improving(vec4 history) { return (uint(history.x) & 1u) != 0u; }

// The kept triangle and its instance, or false.
bool history_kept_triangle(vec4 history, out uint triangle, out uint instance) {
  triangle = uint(history.y) - 1u;
  instance = uint(history.x) >> 1;
  return history.y > 0.0;
}
