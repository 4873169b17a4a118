// What the shading passes (quad_visibility.comp, shade.comp) read: the
// G-buffer, the frame, the lights, the push constants, the fields and their
// march, and the quad pass's samples; and how a pixel's surface and its
// lights are set up for the march.
layout(binding = 0, rgba32f) uniform readonly image2D g_position;
layout(binding = 1, rgba32f) uniform readonly image2D g_normal;
layout(binding = 2, rgba32f) uniform readonly image2D g_albedo;
layout(std430, binding = 4) readonly buffer Lights { GpuLight lights[]; };
layout(std140, binding = 5) uniform Frame { FrameData frame; };
layout(push_constant) uniform Push { ShadePush pc; };
// The visibility this pipeline computes (kVisibility*; as pc.visibility_mode),
// and its part of the shading (kShade*): constants, so that the compiler
// drops the code of the other methods and parts. (Lavapipe runs both sides
// of a branch under a mask: dead code costs every pixel.)
layout(constant_id = 0) const uint kVisibilityMode = kVisibilitySignedSdf;
layout(constant_id = 1) const uint kShadeStage = kShadeFull;
#include "sdf_fields.glsl.h"  // bindings 3, 11: the fields marched
#include "sdf_march.glsl.h"
#define RTSDF_RAY_BINDING 15     // bindings 15 to 18: the scene's BVHs (raytraced)
#include "ray_trace.glsl.h"
// Visibility at a quarter of the pixels. The world light's is low-frequency:
// quad_visibility.comp marches it for one pixel of each 2x2 quad (which one
// changes every frame, so that accumulation covers all four), and
// shade.comp takes it for every pixel from the quads around it on its own
// surface, marching its own only where none is (Unreal's distance-field AO is
// computed at reduced resolution and upsampled alike). In a kShadeShared
// frame (the viewport's first after a change) the lights' visibility is
// taken so too, and the pixels that find no sample on their surface are
// listed and shaded by a kShadeFill pass instead.
// quad_samples: one texel per quad: xyz = the sample's normal, w = its world
// light (< 0: no surface at the sample's pixel). quad_lights: light l's
// visibility at quad q in [l * quads + q], quads = quad_count() (< 0: not
// marched, the light is behind the sample's surface).
#ifdef RTSDF_QUAD_PASS
layout(binding = 12, rgba32f) uniform writeonly image2D quad_samples;
layout(std430, binding = 13) writeonly buffer QuadLights { float quad_lights[]; };
#else
layout(binding = 12, rgba32f) uniform readonly image2D quad_samples;
layout(std430, binding = 13) readonly buffer QuadLights { float quad_lights[]; };
#endif
// The accumulation the shading adds this frame's sample to (the quad pass
// only reads which pixels the temporal keep pass kept).
#ifdef RTSDF_QUAD_PASS
layout(binding = 7, rgba32f) uniform readonly image2D accum_passes;
#else
layout(binding = 6, rgba32f) uniform image2D accum_color;   // rgb = Combined, a = coverage
// x = Depth (the nearest seen), y = Shadow (visibility), z = samples in the mean, w = the farthest depth seen
layout(binding = 7, rgba32f) uniform image2D accum_passes;
// The samples' second moments (sample_moments.glsl.h), for the temporal resolve
layout(binding = 20, rgba32f) uniform image2D accum_moments;
#endif

// With pc.listed_tiles, the tiles holding pixels to shade, listed by the
// temporal keep pass (temporal_keep.comp) or by the converged test after the
// frame before (temporal_converged.comp): the pixel and quad passes run on
// those alone.
layout(std430, binding = 19) readonly buffer KeptTiles { uint tile_words[]; };
#include "kept_tiles.glsl.h"

// Whether this frame shades nothing of this pixel: its tile is not listed
// (the rest of the tile's pixels were kept, or all have converged), or the
// keep pass took its history as this frame's sample.
bool left_unshaded(ivec2 pixel) {
  // (a pixel of a tile the keep pass did not list is kept, and may not carry
  // its mark: the keep pass runs over fewer tiles than the quad pass reads)
  return pc.listed_tiles == 1u &&
         (!tile_listed(pixel_tiles(), pixel / int(kTemporalTile)) || imageLoad(accum_passes, pixel).z == kKeptSample);
}

// The pixels a kShadeShared pass left to kShadeFill (x | y << 16), and the
// fill's indirect dispatch: one group of 64 per 64 listed. The quad pass
// lists quads alike for its kShadeSkyList pass.
layout(std430, binding = 14) buffer FillList {
  uvec3 fill_groups;
  uint fill_count;
  uint fill_pixels[];
};

// Leaves a pixel (a quad, in the quad pass) to the pass over the list.
void list_for_next_pass(ivec2 at) {
  uint index = atomicAdd(fill_count, 1u);
  if (index % 64u == 0u) atomicAdd(fill_groups.x, 1u);
  fill_pixels[index] = uint(at.x) | uint(at.y) << 16u;
}

// In a pass over the list (dispatched by its groups, 8 x 8 each): what this
// invocation takes; false past the list's end.
bool listed_for_this_pass(out ivec2 at) {
  uint index = gl_WorkGroupID.x * 64u + gl_LocalInvocationIndex;
  if (index >= fill_count) return false;
  at = ivec2(fill_pixels[index] & 0xffffu, fill_pixels[index] >> 16u);
  return true;
}

ivec2 quad_grid() { return (pc.image_size + 1) / 2; }
int quad_count() { return quad_grid().x * quad_grid().y; }

// Whether the world light is marched at all (the same for every pixel).
bool wants_sky() { return kVisibilityMode != kVisibilityShadowMaps && dot(frame.ambient.rgb, frame.ambient.rgb) > 0.0; }

// The pixel a quad's sample is marched for this frame.
ivec2 quad_sample_pixel(ivec2 quad) {
  int frame_index = pc.accumulation_frame;
  return min(2 * quad + ivec2(frame_index & 1, (frame_index >> 1) & 1), pc.image_size - 1);
}

// The camera-facing side's normal at a G-buffer pixel.
vec3 facing_normal(ivec2 pixel, vec3 p) {
  vec3 n = imageLoad(g_normal, pixel).xyz;
  vec3 to_camera = frame.camera_position.w > 0.5 ? -frame.camera_forward.xyz : frame.camera_position.xyz - p;
  return dot(n, to_camera) < 0.0 ? -n : n;
}

// Where the march starts off a surface at p (normal n) held by a field of
// world voxel receiver_voxel (0: in none): a nudge along the normal keeps a
// caster's march off its own surface (see shade.comp's main).
vec3 march_origin(vec3 p, vec3 n, float receiver_voxel) { return p + n * (pc.caster_offset * receiver_voxel); }

#include "same_surface.glsl.h"

// A light as a point p (on a surface) sees it, and the march towards it
// from origin (p's march start).
struct LightPath {
  int light;        // its index in `lights`
  vec3 dir;         // towards the light from p, for the shading
  vec3 march_dir;   // towards it from origin
  vec3 irradiance;  // at p, before the cosine
  float t_max;      // the march's end
  float tan_radius; // tangent of the light's angular radius seen from origin (0: hard shadows)
};

LightPath light_path(int index, vec3 p, vec3 origin) {
  GpuLight light = lights[index];
  LightPath path;
  path.light = index;
  uint type = uint(light.position.w);
  path.irradiance = light.radiance.rgb;
  if (type == kLightSun) {
    path.dir = path.march_dir = -light.direction.xyz;
    path.t_max = 1e10;
    path.tan_radius = light.direction.w;
    return path;
  }
  // Lighting from p itself, so that every method shades alike.
  vec3 to_light = light.position.xyz - p;
  float distance = length(to_light);
  path.dir = to_light / max(distance, 1e-6);
  path.irradiance /= max(distance * distance, 1e-8);
  float cos_axis = dot(-path.dir, light.direction.xyz);
  // As Cycles: inside the cone, the cosine to the axis times a smoothstep over the blend.
  if (type == kLightSpot)
    path.irradiance *= max(cos_axis, 0.0) * smoothstep(light.spot.x, light.spot.x + light.spot.y, cos_axis);
  if (light.spot.z > 0.5) path.irradiance *= max(cos_axis, 0.0);
  vec3 march_to_light = light.position.xyz - origin;
  float march_distance = length(march_to_light);
  path.march_dir = march_to_light / max(march_distance, 1e-6);
  path.t_max = max(march_distance - light.direction.w, 0.0);
  path.tan_radius = light.direction.w / max(march_distance, 1e-6);
  return path;
}

// Whether a light reaches p's side of its surface at all (no march needed where not).
bool faces_light(LightPath path, vec3 n) { return dot(n, path.dir) > 0.0 && dot(path.irradiance, path.irradiance) > 0.0; }

// raytraced: whether a ray from p (on a surface of normal n) along dir meets
// no triangle within t_max. It starts a hair off the surface (a ten
// thousandth of its distance from the camera), so that the surface does not
// hide itself.
bool ray_reaches(vec3 p, vec3 n, vec3 dir, float t_max) {
  vec3 start = p + n * (0.2 * same_surface_distance(p));
  bool front;
  uint triangle, instance;
  return trace_scene(start, dir, t_max, true, front, triangle, instance) >= t_max;
}

// The share of `count` rays from p towards points of a light's disk that
// reach it; over frames, each pixel's rays walk on through one sequence of
// points (disk_direction), so their mean converges to the exact share.
float rays_to_light(LightPath path, vec3 p, vec3 n, ivec2 pixel, int count) {
  uint seed = uint(path.light);
  vec2 start = vec2(hash(uvec3(pixel, 0x2000u + seed)), hash(uvec3(pixel.yx, 0x3000u + seed)));
  float reached = 0.0;
  for (int k = 0; k < count; ++k) {
    vec3 dir = disk_direction(path.march_dir, path.tan_radius, start, pc.sequence * uint(count) + uint(k));
    if (ray_reaches(p, n, dir, path.t_max)) reached += 1.0;
  }
  return reached / float(count);
}

// The exact rays per light at `pixel`: pc.exact_rays, pc.short_history_rays
// times as many where the keep pass marked history short. There the frame
// shown is half this sample or all of it, and a share of 4 binary rays (0,
// 1/4, ... 1) made a moved penumbra speckled where the still frame, 16
// samples of 4, is smooth (docs/benchmarks.md).
int exact_rays_at(ivec2 pixel) {
  bool short_history = pc.listed_tiles == 1u && imageLoad(accum_passes, pixel).z == kShortHistorySample;
  return int(pc.exact_rays) * (short_history ? int(pc.short_history_rays) : 1);
}

// The share of a light reaching a receiver (held by a field of world voxel
// receiver_voxel, 0: in none; of normal n) from its march start `origin`: the
// march starts pc.receiver_clearance of its voxels along the ray and escapes its own
// shell within two. raytraced: one ray towards a point of the light's disk,
// new every frame (its 0 or 1 averages over accumulation frames to the share).
// Hybrid: the march only tells lit from shadowed where the field is sure
// (visibility's classify); where it is not, pc.exact_rays rays decide, as
// raytraced's do (AMD's hybrid shadows trace rays alike, where the shadow
// map cannot tell).
// Whether this pixel's shading traced rays where its field was unsure (the exact_rays field view).
bool traced_exactly = false;

// other_surface_near at a surface point, found once for all the lights it
// marches (it depends on the point alone): -1 not yet, else 0 or 1, at
// unseen_point.
int unseen_caster = -1;
vec3 unseen_point;
bool caster_where_unseen(vec3 p, float unseen, float receiver_voxel) {
  if (unseen_caster < 0 || p != unseen_point) {
    unseen_point = p;
    unseen_caster = other_surface_near(p, unseen, receiver_voxel) ? 1 : 0;
  }
  return unseen_caster == 1;
}

float march_light(LightPath path, vec3 origin, vec3 n, float receiver_voxel, float jitter, ivec2 pixel) {
  if (kVisibilityMode == kVisibilityRayTraced) return rays_to_light(path, origin, n, pixel, 1);
  float t_min = pc.receiver_clearance * receiver_voxel, escape = 2.0 * receiver_voxel;
  if (kVisibilityMode == kVisibilityHybrid) {
    bool crossed_sheet;  // (never when classifying)
    float v = visibility(origin, path.march_dir, t_min, path.t_max, path.tan_radius, jitter, escape, n, false, true,
                         crossed_sheet);
    vec3 p = origin - n * (pc.caster_offset * receiver_voxel);  // (the rays start at the surface itself)
    // (lit, unless another caster lies where the march did not look: its start and jitter)
    float unseen = t_min + pc.shadow_epsilon * receiver_voxel;
    if (v > 0.0 && receiver_voxel > 0.0 && caster_where_unseen(p, unseen, receiver_voxel)) v = -1.0;
    if (v >= 0.0) return v;
    traced_exactly = true;
    return rays_to_light(path, p, n, pixel, exact_rays_at(pixel));
  }
  return light_visibility(origin, path.march_dir, t_min, path.t_max, path.tan_radius, jitter, escape, pixel);
}

// The share of the world light reaching a receiver (see march_light and
// sky_visibility). raytraced: two rays, cosine-distributed over the
// hemisphere around n and new every frame.
float world_light_visibility(vec3 origin, vec3 n, float receiver_voxel, float jitter, ivec2 pixel) {
  if (kVisibilityMode != kVisibilityRayTraced) return sky_visibility(origin, n, receiver_voxel, jitter, pixel);
  float sum = 0.0;
  for (uint k = 0u; k < 2u; ++k) {
    vec3 dir = sky_direction(n, pixel, k);
    if (!enters_sky_blocker(origin, dir) && ray_reaches(origin, n, dir, 1e10)) sum += 1.0;
  }
  return 0.5 * sum;
}
