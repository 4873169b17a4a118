// Debug views of the distance fields (ShadePush::debug.x, Render Properties
// > Field View), drawn in place of the shaded image so an artist can see why
// a shadow leaks or smears:
// - kDebugDistanceSlice: a section at the plane z = debug.y (what is in
//   front of it cut away): the fields' signed distance where each pixel's ray
//   meets the plane, as a heat map (blue inside, a line every voxel, cyan tint
//   where a brick is stored), the image dimmed where no field is near;
// - kDebugMarchSteps: the fields' zero level sphere-traced from the camera,
//   coloured by the steps it took (what the shadow march pays there);
// - kDebugFieldResolution: each surface by its field's voxel against the
//   pixel's footprint there (blue finer than a pixel, yellow coarser);
// - kDebugExactRays: the shaded image, magenta where the hybrid traced rays
//   (where the field could not tell lit from shadowed).
// Needs sdf_fields.glsl.h, `frame` and `pc`.

// Matplotlib's "inferno" ramp (nine even stops), t in [0, 1]: black, purple, orange, pale yellow.
vec3 heat_color(float t) {
  const vec3 stops[9] = vec3[](vec3(0.001, 0.000, 0.014), vec3(0.129, 0.047, 0.291), vec3(0.342, 0.062, 0.429),
                               vec3(0.541, 0.135, 0.415), vec3(0.736, 0.216, 0.330), vec3(0.894, 0.353, 0.194),
                               vec3(0.978, 0.558, 0.035), vec3(0.975, 0.798, 0.206), vec3(0.988, 0.998, 0.645));
  float x = clamp(t, 0.0, 1.0) * 8.0;
  int i = min(int(x), 7);
  return mix(stops[i], stops[i + 1], x - float(i));
}

// Pixel centre's ray: where it leaves the near plane and where it is headed
// (perspective or orthographic alike).
void camera_ray(ivec2 pixel, out vec3 origin, out vec3 dir) {
  vec2 ndc = (vec2(pixel) + 0.5) / vec2(pc.image_size) * 2.0 - 1.0;
  mat4 clip_to_world = inverse(frame.steady_world_to_clip);
  vec4 near = clip_to_world * vec4(ndc, 0.0, 1.0), far = clip_to_world * vec4(ndc, 1.0, 1.0);
  origin = near.xyz / near.w;
  dir = normalize(far.xyz / far.w - origin);
}

// Whether the field stores a brick for the cell at q (its voxel space).
bool brick_stored(FieldInstance f, vec3 q) {
  ivec3 cell, brick;
  return brick_slot(f, q, cell, brick) < uint(f.dims.w);
}

vec3 distance_slice_color(ivec2 pixel, vec3 shaded) {
  vec3 origin, dir;
  camera_ray(pixel, origin, dir);
  // A section: what lies between the camera and the plane is cut away.
  float t = abs(dir.z) > 1e-6 ? (pc.field_view_height - origin.z) / dir.z : -1.0;
  if (t <= 0.0) return 0.35 * shaded;  // (the plane is behind the camera)
  vec3 p = origin + t * dir;
  int count = pc.field_instances == 0u ? 0 : gather_fields(p, vec3(1.0), 0.0, 0.0, pc.field_reach);
  vec3 d = nearby_distance(p, count < 0 ? RTSDF_MAX_NEARBY_FIELDS : count);
  if (min(d.x, d.y) >= kFarAway) return 0.35 * shaded;  // (no field near)
  float voxels = min(d.x, d.y) / max(d.z, 1e-12);
  vec3 color = voxels < 0.0 ? vec3(0.1, 0.3, 1.0) * (0.6 + 0.4 * exp(voxels)) : heat_color(voxels / 16.0);
  float line = abs(fract(voxels + 0.5) - 0.5);  // (0 on every whole voxel)
  color *= 0.75 + 0.25 * smoothstep(0.0, 0.08, line);
  bool stored = false;
  for (int k = 0; k < (count < 0 ? RTSDF_MAX_NEARBY_FIELDS : count); ++k) {
    FieldInstance f = field_instances[nearby_fields[k]];
    vec3 q = (f.world_to_field * vec4(p, 1.0)).xyz;
    if (all(greaterThanEqual(q, f.box_lo.xyz)) && all(lessThanEqual(q, f.box_hi.xyz)) && brick_stored(f, q))
      stored = true;
  }
  return stored ? mix(color, vec3(0.3, 1.0, 1.0), 0.25) : color;
}

vec3 march_steps_color(ivec2 pixel) {
  const int kMostSteps = 256;
  vec3 origin, dir;
  camera_ray(pixel, origin, dir);
  int count = pc.field_instances == 0u ? 0 : gather_fields(origin, safe_inverse(dir), 0.0, kFarAway, 0.0);
  if (count == 0) return vec3(0.05);  // (no field on the ray)
  count = count < 0 ? RTSDF_MAX_NEARBY_FIELDS : count;
  float t = 0.0;
  for (int step = 0; step < kMostSteps; ++step) {
    vec3 d = nearby_distance(origin + t * dir, count);
    float distance = min(d.x, d.y);
    if (distance >= kFarAway) break;  // (past every field)
    if (distance < 0.5 * d.z) return heat_color(0.2 + 0.8 * float(step) / 48.0);
    t += max(distance, 0.5 * d.z);
  }
  return vec3(0.05);
}

vec3 field_resolution_color(vec4 position, float receiver_voxel, vec3 shaded) {
  if (position.w <= 0.0) return shaded;
  float brightness = 0.45 + 0.55 * clamp(dot(shaded, vec3(0.2126, 0.7152, 0.0722)) * 2.0, 0.0, 1.0);
  if (receiver_voxel <= 0.0) return vec3(0.5) * brightness;  // (in no field: a receiver only)
  // The world width of a pixel at the surface: one pixel over in clip space, back to the world.
  vec4 clip = frame.steady_world_to_clip * vec4(position.xyz, 1.0);
  vec4 beside = inverse(frame.steady_world_to_clip) * (clip + vec4(2.0 * clip.w / float(pc.image_size.x), 0.0, 0.0, 0.0));
  float footprint = max(distance(beside.xyz / beside.w, position.xyz), 1e-12);
  return heat_color(0.5 + 0.125 * log2(receiver_voxel / footprint)) * brightness;
}
