// The shadow march through the distance fields (sdf_fields.glsl.h): a light's
// visibility (a cone towards a disk) and the world light's (cones over the
// hemisphere). Needs the Frame buffer (`frame`), the ShadePush constants
// (`pc`) and kVisibilityMode declared before it.
float hash(uvec3 v) {
  v = v * 1664525u + 1013904223u;
  v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
  v ^= v >> 16u;
  v.x += v.y * v.z;
  return float(v.x) * (1.0 / 4294967296.0);
}

// Interleaved sampling (Keller and Heidrich, 2001): the 16 pixels of each
// 4x4 tile take 16 consecutive points of a low-discrepancy (Kronecker)
// sequence, in dither-matrix order (neighbours far apart in it), all turned
// by one random offset (Cranley-Patterson) new every frame and tile. Each
// pixel's samples are then as independent from frame to frame as random
// ones (its mean converges to the true one), while a small neighbourhood's
// in one frame spread evenly: the temporal resolve's clip and filter, which
// read a few pixels around each of one frame, see nearly their converged
// value, not a few noisy samples. Each dimension (`salt`) has its own offset, so that
// they are not correlated.
uint tile_index(ivec2 pixel) {
  const uint kDither[16] = uint[16](0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);
  return kDither[(pixel.x & 3) + 4 * (pixel.y & 3)];
}
uint pcg(uint v) {  // (Jarzynski and Olano, 2020: nested, a hash of several integers)
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}
float frame_offset(ivec2 pixel, uint salt) {
  uvec2 tile = uvec2(pixel >> 2);
  return float(pcg(tile.x + pcg(tile.y + pcg(pc.sequence * 16u + salt)))) * (1.0 / 4294967296.0);
}

// The pixel's golden-ratio (1D) and R2 (2D) points; index: its place among
// the tile's points this frame (tile_index, or more per pixel).
float golden_point(ivec2 pixel, uint index, uint salt) {
  return fract(frame_offset(pixel, salt) + float(index * 2654435769u) * (1.0 / 4294967296.0));
}
vec2 r2_point(ivec2 pixel, uint index, uint salt) {
  vec2 offset = vec2(frame_offset(pixel, salt), frame_offset(pixel, salt + 1u));
  return fract(offset + vec2(uvec2(index * 3242174889u, index * 2447445413u)) * (1.0 / 4294967296.0));
}

// This frame's jitter of a pixel's march start (0 to 1).
float march_jitter(ivec2 pixel) { return golden_point(pixel, tile_index(pixel), 0u); }

// Two unit vectors that make an orthonormal frame with the unit vector n.
void tangent_frame(vec3 n, out vec3 t, out vec3 b) {
  t = normalize(abs(n.z) < 0.9 ? cross(n, vec3(0.0, 0.0, 1.0)) : cross(n, vec3(1.0, 0.0, 0.0)));
  b = cross(n, t);
}

// A direction towards the index-th point of a light's disk (tan_radius seen
// along dir): each pixel's points (over frames, and over its rays in a frame)
// follow the R2 sequence from a random start (`start`, 0 to 1), evenly spread
// over the disk.
vec3 disk_direction(vec3 dir, float tan_radius, vec2 start, uint index) {
  vec3 t, b;
  tangent_frame(dir, t, b);
  vec2 u = fract(start + float(index) * vec2(0.7548776662, 0.5698402910));
  float r = tan_radius * sqrt(u.x), phi = 6.2831853 * u.y;
  return normalize(dir + r * (cos(phi) * t + sin(phi) * b));
}

// This frame's k-th direction of the world light at a pixel: cosine-distributed
// over the hemisphere around n, new every frame.
vec3 sky_direction(vec3 n, ivec2 pixel, uint k) {
  vec3 t, b;
  tangent_frame(n, t, b);
  vec2 u = r2_point(pixel, 2u * tile_index(pixel) + k, 1u);
  float u1 = u.x, u2 = u.y;
  float r = sqrt(u1), phi = 6.2831853 * u2;
  return normalize(t * (r * cos(phi)) + b * (r * sin(phi)) + n * sqrt(max(1.0 - u1, 0.0)));
}

// Share of a disk (the light) left visible by a straight occluder edge at
// signed distance r (in disk radii; r < 0: the edge covers the centre).
float disk_visible(float r) {
  r = clamp(r, -1.0, 1.0);
  return 0.5 + (r * sqrt(1.0 - r * r) + asin(r)) / 3.14159265;
}

// Unit outward normal of the surface nearest the point t along a ray (the
// clearance's gradient by tetrahedral differences half a voxel wide), from
// the fields near it.
vec3 surface_normal_at(vec3 origin, vec3 dir, vec3 inv_dir, float t, float voxel) {
  float e = 0.5 * voxel;
  int count = gather_fields(origin, inv_dir, t - e, t + e, 2.0 * e);
  if (count < 0) count = RTSDF_MAX_NEARBY_FIELDS;
  vec3 p = origin + dir * t;
  const vec3 corners[4] = vec3[4](vec3(1, -1, -1), vec3(-1, -1, 1), vec3(-1, 1, -1), vec3(1, 1, 1));
  vec3 g = vec3(0.0);
  for (int i = 0; i < 4; ++i) g += corners[i] * nearby_distance(p + e * corners[i], count).y;
  return dot(g, g) > 0.0 ? normalize(g) : vec3(0.0);
}

// The part of [t_min, t_max] along a ray that lies in the box of all
// fields, the only place where a clearance is known (field_distance); empty
// (x >= y) where the ray misses it or there are no fields: nothing to march.
vec2 span_in_fields(vec3 origin, vec3 inv_dir, float t_min, float t_max) {
  if (pc.field_instances == 0u) return vec2(1.0, 0.0);
  BvhNode root = field_nodes[0];
  vec2 span = ray_box_span(origin, inv_dir, root.lo.xyz, root.hi.xyz);
  return vec2(max(t_min, span.x), min(t_max, span.y));
}

// Whether a surface other than the receiver's own may lie within `reach`
// of the surface point p: where a light's march from p does not look (it
// starts the receiver's clearance, and up to its jitter, along the ray).
// Those lengths are in the receiver's own voxels (own_voxel), and a large
// receiver's are coarse: IvyGen's stems a centimetre off their wall (4 cm
// voxels) lay wholly within them, and the march called the wall behind
// them lit. The receiver's own field is the one of its voxel that reads
// about 0 at p (another instance of its mesh touching it there passes for
// it); any other whose surface may be within reach (give or take its
// epsilon) may be such a caster.
const float kOwnSurfaceVoxels = 0.5;
bool other_surface_near(vec3 p, float reach, float own_voxel) {
  int count = gather_fields(p, vec3(1.0), 0.0, 0.0, reach);
  if (count < 0) count = RTSDF_MAX_NEARBY_FIELDS;  // (too many: the first that fit, as the march takes them)
  for (int k = 0; k < count; ++k) {
    vec3 d = field_distance(nearby_fields[k], p);  // (outside its box: x bounds the distance)
    if (abs(d.z - own_voxel) <= 1e-4 * own_voxel && abs(d.y) <= kOwnSurfaceVoxels * d.z) continue;
    if (min(d.x, d.y) < reach + pc.shadow_epsilon * d.z) return true;
  }
  return false;
}

// Fraction of the light visible from `origin` along `dir` up to `t_max`;
// tan_radius = tangent of the light's angular radius (0: a hard shadow).
// Each sample's clearance from the surfaces is compared with the light cone's
// radius there, w = t * tan_radius (shadow_epsilon, the paper's stop distance,
// ends hard-shadow marches; thickening soft ones by it made shadows too fat).
// Samples may lie inside an occluder (negative clearance), so the penumbra
// straddles the geometric shadow edge as in Cycles, instead of lying wholly
// outside it as with min(h / w). Between samples outside surfaces, the
// clearance is refined by Aaltonen's triangulation.
// The field is signed only in the fine band: deeper inside a solid it is the
// unsigned coarse distance. A march that goes from negative to a positive
// value further than the step could explain (an SDF changes by at most the
// distance moved) has entered that interior, and reads it negated until it
// reaches the band on the far side.
// An unsigned field (the coarse SDF of jfa_only) cannot tell inside from
// outside: a sample within epsilon of its surfaces blocks the ray (the
// paper's stop), and only clearances above that shell shape the penumbra,
// whose inner half therefore collapses onto the shell.
// Epsilon and the step cap are in voxels of the field nearest each sample
// (fields differ in resolution). Only fields whose box, grown by the longest
// step, the ray passes are read: the march goes in segments, each with the
// fields near it (gather_fields); a segment near too many is halved, one
// near none is skipped. Outside every box (clear of all surfaces by a margin)
// it steps on without narrowing the cone, as a march clipped to one grid does.
// escape: how far along the ray negative samples are skipped until the first
// non-negative one: a receiver that is itself in the SDF may start inside its
// own shell (thin pieces read as slabs a voxel thick on either side). Only
// while they rise (leaving a surface), and when classifying they leave the
// result uncertain: at a corner they may be the other wall's.
// own_normal (0: none): samples whose clearance is the distance to the
// receiver's own tangent plane are not counted: near-tangent cones (the sky's)
// would otherwise see the receiver itself.
// axis_blocks: a cone whose axis enters an occluder sees nothing. For the
// sky's wide cones: the clearance inside an occluder tells how thick it is,
// not how far it reaches sideways, and through a room's walls (far thinner
// than the cone is wide) about half the sky shone in.
// crossed_sheet (out): the axis passed through a sheet of an occluder (left
// it through a face turned away from the one it entered by: a wall, a leaf, a
// plate, not the rim of a solid) or where two solids touch, and the cone was
// not found wholly blocked:
// the returned share is then only a guess (see light_visibility).
// classify: no share, only what the field can tell with epsilon (about its
// own error) to spare: 1 where the whole cone stays epsilon clear of every
// surface, 0 where it lies epsilon deep inside an occluder, and -1 (uncertain)
// elsewhere: in penumbrae, at contact, behind occluders thinner than the
// error (slabs of sheets, leaf cards) and where the march ran out of steps.
float visibility(vec3 origin, vec3 dir, float t_min, float t_max, float tan_radius, float jitter, float escape,
                 vec3 own_normal, bool axis_blocks, bool classify, out bool crossed_sheet) {
  crossed_sheet = false;
  sampled_contact = false;
  vec3 inv_dir = safe_inverse(dir);
  vec2 span = span_in_fields(origin, inv_dir, t_min, t_max);
  if (span.x >= span.y) return 1.0;
  t_min = span.x;
  t_max = span.y;
  const bool unsigned_field = kVisibilityMode == kVisibilityUnsignedSdf;
  float t = t_min, t_start = t_min;
  float ratio = 1.0;  // smallest clearance / cone radius seen
  float previous_h = 0.0, step = 0.0;
  bool deep_inside = false, have_previous = false, jittered = false;
  bool escaping = escape > 0.0 && !unsigned_field;
  float escape_h = -kFarAway;  // (the last sample escaped)
  // The axis's first passage through an occluder: where it entered, where it
  // left, and the voxel there (entry < 0: none yet; exit < 0: still inside).
  float entry = -1.0, exit = -1.0, crossing_voxel = 0.0;
  float deepest = 0.0;  // the lowest clearance on that passage
  bool uncertain = false;  // (classify) some sample's clearance was within epsilon of the cone's radius
  float segment_end = t;  // the fields near [t, segment_end] are gathered
  int nearby = 0;
  FieldInstance only_field;  // when nearby is 1: that field, and the ray in its voxel space
  vec3 field_origin, field_dir;
  for (int i = 0; i < int(pc.max_march_steps) && t < t_max; ++i) {
    if (t >= segment_end) {
      segment_end = t_max;
      for (int halvings = 0; halvings < 8; ++halvings) {
        nearby = gather_fields(origin, inv_dir, t, segment_end, pc.field_reach);
        if (nearby >= 0 || segment_end - t < pc.field_reach) break;
        segment_end = t + 0.5 * (segment_end - t);
      }
      if (nearby < 0) nearby = RTSDF_MAX_NEARBY_FIELDS;  // (too many even close by: the first that fit)
      if (nearby == 0) {
        // No field's box within a step: nothing there to meet or to narrow the cone.
        t = segment_end;
        have_previous = false;
        continue;
      }
      if (nearby == 1) {
        // The segment's one field (the common case) stays in registers, the
        // ray in its voxel space: each sample then reads only texels.
        only_field = field_instances[nearby_fields[0]];
        field_origin = (only_field.world_to_field * vec4(origin, 1.0)).xyz;
        field_dir = mat3(only_field.world_to_field) * dir;
      }
    }
    if (!jittered && nearby == 1) {
      // (the one field's voxel is known without a sample: the jitter costs no step)
      jittered = true;
      t_start = t + jitter * pc.shadow_epsilon * only_field.scale.y;
      t = t_start;
      if (t >= t_max || t >= segment_end) continue;
    }
    vec3 sample_ = nearby == 1 ? field_distance_at(only_field, field_origin + field_dir * t)
                               : nearby_distance_on_ray(origin, dir, t, nearby);
    float h = sample_.y, voxel = sample_.z;
    float epsilon = pc.shadow_epsilon * voxel, max_step = pc.max_step * voxel;
    if (!jittered) {
      // Jittered by up to one epsilon along the light each frame: with the sample
      // positions moving, step patterns (banding) average out over accumulation.
      jittered = true;
      t_start = t + jitter * epsilon;
      t = t_start;
      continue;
    }
    if (h >= kFarAway) {
      // Outside every field's box: clear of every surface by the bound, and
      // nothing there narrows the cone: step the whole bound, but no further
      // than the segment whose fields were gathered.
      have_previous = false;
      t = min(t + max(sample_.x, 0.5 * epsilon), max(segment_end, t + 0.5 * epsilon));
      continue;
    }
    if (escaping) {
      // The receiver's own shell: h rises as the ray leaves its surface. A
      // sample lower than the one before is another occluder the ray goes
      // into (a wall meeting the receiver's wall at a corner): escaping
      // through it let a seam of light through.
      if (h < 0.0 && t < t_start + escape && h >= escape_h) {
        escape_h = h;
        // (within a voxel of the receiver the field cannot tell its own shell
        // from a wall it meets: exact rays decide)
        if (classify) uncertain = true;
        t += 0.5 * epsilon;
        continue;
      }
      escaping = false;
    }
    if (unsigned_field) {
      if (h < epsilon) return 0.0;
      h -= epsilon;
    } else if (h < 0.0) {
      deep_inside = false;
    } else if (deep_inside || (have_previous && previous_h < 0.0 && h - previous_h > step + voxel)) {
      deep_inside = true, h = -h;
    }
    if (classify) {
      float w = tan_radius * t;
      if (h <= -(w + epsilon)) return 0.0;
      bool own_plane = h >= t * dot(dir, own_normal) - 0.5 * epsilon && dot(own_normal, own_normal) > 0.0;
      if (h < w + epsilon && !own_plane) uncertain = true;
      // Clear again after the uncertain stretch: nothing further decides it.
      else if (uncertain && h >= w + epsilon) return -1.0;
    } else {
      if (h < 0.0 && axis_blocks) return 0.0;
      if (h < 0.0 && entry < 0.0) entry = t, crossing_voxel = voxel;
      if (h >= 0.0 && entry >= 0.0 && exit < 0.0) exit = t;
      // (back in within a voxel: one passage, as where a wall's top meets the ceiling the clearance dips below
      // zero, rises within the field's error and falls again)
      else if (h < 0.0 && exit > 0.0 && t - exit < voxel) exit = -1.0;
      if (entry >= 0.0 && exit < 0.0) deepest = min(deepest, h);
      if (tan_radius <= 0.0) {
        if (!unsigned_field && h < epsilon) return 0.0;
      } else {
        float clearance = h, at = t;
        if (have_previous && previous_h > 0.0 && h > 0.0) {
          // Spheres of radius previous_h and h around the last two samples (step
          // apart) meet y back along the ray, d off it. Marching straight away
          // from the receiver they barely touch, back at the start: no estimate there.
          float y = (h * h - previous_h * previous_h + step * step) / (2.0 * step);
          if (y > 0.0 && y < h && t - y > t_start) clearance = sqrt(h * h - y * y), at = t - y;
        }
        float w = tan_radius * max(at, 1e-6);
        bool own_plane = h >= t * dot(dir, own_normal) - 0.5 * epsilon && dot(own_normal, own_normal) > 0.0;
        if (!own_plane) ratio = min(ratio, clearance / w);
        if (ratio <= -1.0) return 0.0;
      }
    }
    previous_h = h;
    have_previous = true;
    // Through the thickened surface in small steps, elsewhere sphere tracing
    // capped at max_step, or at a third of the cone's radius where that is
    // more: a wide cone (the sky's) resolves no finer than its own width (as
    // cone-traced AO grows its steps), and a closest approach missed between
    // samples that far apart moves the ratio by less than 1/6.
    float cone_step = tan_radius * t * (1.0 / 3.0);
    step = clamp(abs(h), 0.5 * epsilon, max(max_step, cone_step));
    // The cap matters only where the cone may narrow: a step that keeps the
    // clearance above the cone's radius (plus epsilon) all along, by the
    // clearance's bound h - s at s further on, skips nothing that could count.
    // Far from surfaces (the middle of a room, the open space around a
    // model) the march then strides as plain sphere tracing does.
    if (h > 0.0) step = max(step, (h - tan_radius * t - epsilon) / (1.0 + tan_radius));
    step = min(step, max(sample_.x, 0.5 * epsilon));  // (no further than the boxes of fields not yet entered)
    if (step > max_step) step = min(step, max(segment_end - t, max_step));  // (gathered fields only reach so far)
    t += step;
  }
  if (classify) return uncertain || t < t_max ? -1.0 : 1.0;
  bool met_contact = sampled_contact;  // (the march's samples only: the normals' probes below read fields too)
  if (tan_radius <= 0.0) return 1.0;
  // (the normals only now, for the one passage, and each probe written once: probed in the loop, or inlined at
  // several places, they made every march 1.5 to 3x slower on lavapipe)
  if (exit > 0.0) {
    vec3 normals[2];
    for (int k = 0; k < 2; ++k) normals[k] = surface_normal_at(origin, dir, inv_dir, k == 0 ? entry : exit, crossing_voxel);
    // A sheet: left through a face turned away from the one it entered by.
    // Or a solid too thin for the field (within a voxel deep all through)
    // crossed at a corner, its faces at an angle (a room's walls meeting, a
    // ceiling slab over a wall): the clearance there says how thin it is,
    // not how far it reaches. Told from the rim of a solid by a chord
    // - over four times that depth (a right-angled edge gives under three),
    // - over two and a half voxels (a piece thinner than a voxel, a slat
    //   crossed at its edge, reads as a slab a voxel thick, and the ray
    //   through that slab widens its shadow more than the cone errs),
    // - and longer than the cone is wide there (a small solid's corner,
    //   which the cone's other rays pass, keeps the cone's estimate).
    float facing = dot(normals[0], normals[1]);
    float chord = exit - entry;
    bool thin_corner = facing < 0.5 && -deepest < crossing_voxel &&
                       chord > max(max(4.0 * -deepest, 2.5 * crossing_voxel), tan_radius * exit);
    crossed_sheet = facing < -0.5 || thin_corner;
  }
  // (or passed where two fields' solids touch: nearby_distance)
  if (met_contact) crossed_sheet = true;
  return disk_visible(ratio);
}

// Share of a light (a disk of tan_radius seen from origin along dir) reaching
// origin. The cone march measures it from the clearances along the axis,
// which holds for the rim of a solid: outside surfaces the clearance is the
// distance in every direction, and inside it is the depth below the rim.
// Where the axis crosses a sheet (a wall, a leaf card, a plate), or a solid
// as thin as the field's voxels at a corner (where two walls or a wall and
// the ceiling meet), the clearance inside tells only its thickness, not how
// far it reaches sideways: a room's walls and ceiling, thinner than the
// sun's cone is wide, let a sixth of the sun through (the interior sample),
// and lines of it across the floor from the corners. There, one ray
// towards a random point of the light's disk (new each frame) stands in: its
// 0 or 1 averages over accumulation frames to the true share, whatever the
// occluder's shape.
float light_visibility(vec3 origin, vec3 dir, float t_min, float t_max, float tan_radius, float jitter, float escape,
                       ivec2 pixel) {
  // The cone, then where it crossed a sheet the ray (one call site: two made
  // the shader's march twice as large, and every march slower on lavapipe).
  // The ray is a cone a thousandth as wide, blocked where its axis enters a
  // surface, not epsilon short of it as a hard shadow's march stops, which
  // would widen every shadow by epsilon.
  vec3 march_dir = dir;
  float cone = tan_radius;
  float v = 1.0;
  for (int pass = 0; pass < 2; ++pass) {
    bool crossed_sheet;
    v = visibility(origin, march_dir, t_min, t_max, cone, jitter, escape, vec3(0.0), false, false, crossed_sheet);
    if (!crossed_sheet || tan_radius <= 0.0) break;
    march_dir = disk_direction(dir, tan_radius, vec2(hash(uvec3(pixel, 0x1157u)), hash(uvec3(pixel.yx, 0x1158u))),
                               pc.sequence);
    cone = 1e-3 * tan_radius;
  }
  return v;
}

// Share of the world light (the sky, uniform) reaching p: two cone marches
// per frame over the hemisphere around n, cosine-distributed and turned every
// frame, so that accumulation averages many. Cycles' direct light includes
// the world, occluded by the scene: without this, a room lit through a
// window glowed everywhere with the world colour. Shadow maps have no view
// of the sky: csm_evsm leaves the world light unoccluded.
// Whether a ray from p along dir enters one of the flat receivers left out of
// the SDF (a ground) ahead of p; p's own surface, which it leaves at once, does not count.
bool enters_sky_blocker(vec3 p, vec3 dir) {
  vec3 inv = safe_inverse(dir);
  for (int i = 0; i < int(frame.ambient.w); ++i) {
    vec3 lo = frame.sky_blockers[2 * i].xyz, hi = frame.sky_blockers[2 * i + 1].xyz;
    vec3 pad = vec3(1e-4 * length(hi - lo));  // a plane's box has no thickness
    vec2 span = ray_box_span(p, inv, lo - pad, hi + pad);
    if (span.x > 0.0 && span.x <= span.y) return true;
  }
  return false;
}

// How far the sky's cones march (to the fields' far side).
const float kSkyDistance = 1e10;

// Whether this frame's sky cones at a receiver (see sky_visibility) need no
// march: each enters a sky blocker (0) or passes no field's box (1); `sky`
// is then their share.
bool sky_without_march(vec3 origin, vec3 n, float receiver_voxel, ivec2 pixel, out float sky) {
  float sum = 0.0;
  for (uint k = 0u; k < 2u; ++k) {
    vec3 dir = sky_direction(n, pixel, k);
    if (enters_sky_blocker(origin, dir)) continue;
    vec2 span = span_in_fields(origin, safe_inverse(dir), pc.sky_receiver_clearance * receiver_voxel, kSkyDistance);
    if (span.x < span.y) return false;
    sum += 1.0;
  }
  sky = 0.5 * sum;
  return true;
}

// receiver_voxel: the world voxel of the field holding the receiver (0: in none).
float sky_visibility(vec3 origin, vec3 n, float receiver_voxel, float jitter, ivec2 pixel) {
  bool in_sdf = receiver_voxel > 0.0;
  float sum = 0.0;
  for (uint k = 0u; k < 2u; ++k) {
    vec3 dir = sky_direction(n, pixel, k);
    if (enters_sky_blocker(origin, dir)) continue;
    bool crossed_sheet;  // (never with axis_blocks)
    sum += visibility(origin, dir, pc.sky_receiver_clearance * receiver_voxel, kSkyDistance, 0.35, jitter, 2.0 * receiver_voxel,
                      in_sdf ? n : vec3(0.0), true, false, crossed_sheet);
  }
  return 0.5 * sum;
}

