// Whether a point lies on the surface of a sample (a point and its unit
// normal): a close normal, and within same_surface_distance of its tangent
// plane. The quad pass's samples are shared (quad_share.glsl.h) and the
// temporal resolve filters a frame's sample (temporal_resolve.comp) only
// over pixels on one surface. Needs the Frame buffer (`frame`).

// How far off a sample's tangent plane a point may lie and still be on its
// surface: a thousandth of its distance to the camera's plane.
float same_surface_distance(vec3 p) {
  return 1e-3 * abs(dot(p - frame.camera_position.xyz, frame.camera_forward.xyz)) + 1e-6;
}

bool on_sample_surface(vec3 p, vec3 n, vec3 sample_point, vec3 sample_normal) {
  return dot(n, sample_normal) >= 0.9 && abs(dot(p - sample_point, sample_normal)) <= same_surface_distance(sample_point);
}
