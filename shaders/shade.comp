#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
// Shading: Lambert direct light times visibility, plus the world colour,
// averaged over accumulation frames (each with its own sub-pixel and
// shadow-origin jitter). Visibility (kVisibilityMode) either marches an SDF
// towards the light (trilinear samples, stop below shadow_epsilon, steps
// capped at max_step) with the cone penumbra, improved by Aaltonen's
// triangulation between consecutive samples (Claybook, GDC 2018): the signed
// fine SDF, or for the jfa_only baseline the unsigned coarse one, bound to
// the same bindings; or, for the shadow-map baselines, looks up EVSM shadow
// maps (shadow_map_lookup.glsl.h); or, for raytraced, traces rays through the scene's BVHs towards a
// random point of each light every frame, which average over accumulation
// frames to the exact share. Only visibility differs between the methods. The fields
// (sdf_fields.glsl.h) are many in the object-space design, one per placed
// mesh, and one for the whole-scene methods. The pipeline's kShadeStage
// says which pixels it shades and whether it marches (shade_inputs.glsl.h).
#include "shared.h"

layout(local_size_x = kTemporalTile, local_size_y = kTemporalTile) in;  // (a listed tile per work group, see kept_tiles.glsl.h)
#include "shade_inputs.glsl.h"  // the G-buffer, the frame, the lights, the fields, the march, the quad samples, the accumulation
// The field view drawn in place of the image (kDebug*; as pc.field_view): a
// constant, as the method is, since lavapipe pays for the views' code in
// every pixel even where a branch skips it (it made the shading 2.5x slower).
layout(constant_id = 2) const uint kFieldView = kDebugNone;
#include "shadow_map_lookup.glsl.h"  // csm_evsm, csm_jitter
#include "field_views.glsl.h"        // what the fields look like, in place of the image
#include "quad_share.glsl.h"         // the quad pass's samples shared with the pixels on their surface
#include "sample_moments.glsl.h"     // the second moments beside the running means

void main() {
  ivec2 pixel;
  if (kShadeStage == kShadeFill) {
    if (!listed_for_this_pass(pixel)) return;
  } else {
    pixel = pc.listed_tiles == 1u ? listed_tile(pixel_tiles()) * int(kTemporalTile) + ivec2(gl_LocalInvocationID.xy)
                                  : ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, pc.image_size))) return;
    if (left_unshaded(pixel)) return;  // (its sample is history's, written by the keep pass; or it converged)
  }
  vec4 position = imageLoad(g_position, pixel);
  vec3 color = frame.ambient.rgb;
  float depth = 1e10, shadow = 1.0;
  bool holdout = position.w > 0.5 * (kShadedSurface + kHoldoutSurface);
  if (holdout) {
    color = vec3(0.0);  // (and no coverage: the hole shows what is composited behind)
    depth = dot(position.xyz - frame.camera_position.xyz, frame.camera_forward.xyz);
  } else if (position.w > 0.0) {
    vec3 p = position.xyz;
    vec3 n = facing_normal(pixel, p);  // shade the side the camera sees
    vec4 albedo_voxel = imageLoad(g_albedo, pixel);
    vec3 albedo = albedo_voxel.rgb;
    float receiver_voxel = albedo_voxel.a;  // of the field holding this surface (0: in none)
    bool in_sdf = receiver_voxel > 0.0;
    depth = dot(p - frame.camera_position.xyz, frame.camera_forward.xyz);
    float lit = 0.0, unshadowed = 0.0;
    float jitter = march_jitter(pixel);
    // The march follows the ray from the shading point itself (an offset along
    // the normal would move every shadow edge inward by offset * tan(angle)).
    // On a surface that is in the SDF it starts pc.receiver_clearance voxels along the ray, so
    // the receiver does not shadow itself; a surface left out of the SDF (a
    // ground that cannot shadow anything) starts at once, so contact shadows
    // reach the objects resting on it. A nudge along the normal (pc.caster_offset
    // voxels: a quarter of a fine SDF's, more for the thick shell of the
    // unsigned coarse one) keeps a caster's march off its own surface.
    vec3 origin = march_origin(p, n, receiver_voxel);
    float sky = 1.0;
    if (wants_sky()) {
      sky = shared_visibility(pixel, p, n, -1);
      if (sky < 0.0 && kShadeStage == kShadeShared) {
        list_for_next_pass(pixel);
        return;
      }
      if (sky < 0.0) sky = world_light_visibility(origin, n, receiver_voxel, jitter, pixel);
    }
    color = albedo * frame.ambient.rgb * sky;
    for (int l = 0; l < pc.light_count; ++l) {
      LightPath path = light_path(l, p, origin);
      if (!faces_light(path, n)) continue;
      float v;
      if (lights[l].spot.w > 0.5) {
        v = 1.0;  // (its shadow switched off)
      } else if (kShadeStage == kShadeShared) {
        v = shared_visibility(pixel, p, n, l);
        if (v < 0.0) {
          list_for_next_pass(pixel);
          return;
        }
      } else if (kVisibilityMode == kVisibilityShadowMaps) {
        v = shadow_map_visibility(l, p, n, path.dir, in_sdf, jitter);
      } else {
        v = march_light(path, origin, n, receiver_voxel, jitter, pixel);
      }
      vec3 direct = path.irradiance * dot(n, path.dir);
      color += albedo * direct * v;
      float weight = dot(direct, vec3(0.2126, 0.7152, 0.0722));
      lit += weight * v;
      unshadowed += weight;
    }
    shadow = unshadowed > 0.0 ? lit / unshadowed : 1.0;
  }
  if (kFieldView == kDebugDistanceSlice) color = distance_slice_color(pixel, color);
  if (kFieldView == kDebugMarchSteps) color = march_steps_color(pixel);
  if (kFieldView == kDebugFieldResolution) color = field_resolution_color(position, imageLoad(g_albedo, pixel).a, color);
  if (kFieldView == kDebugExactRays && traced_exactly) color = mix(color, vec3(1.0, 0.0, 1.0), 0.6);
  // A running mean over the samples in each pixel: the accumulation frames
  // since begin(), and the reprojected history's (temporal_resolve.comp).
  vec4 previous_color = pc.accumulation_frame == 0 ? vec4(0.0) : imageLoad(accum_color, pixel);
  vec4 previous_passes = pc.accumulation_frame == 0 ? vec4(0.0) : imageLoad(accum_passes, pixel);
  float samples = previous_passes.z, w = 1.0 / (samples + 1.0);
  imageStore(accum_color, pixel, mix(previous_color, vec4(color, position.w > 0.0 && !holdout ? 1.0 : 0.0), w));
  // The depths the pixel's samples saw, nearest to farthest: a pixel on a
  // silhouette holds both surfaces (the Depth pass is the nearest).
  float seen = position.w > 0.0 ? depth : kNothingHitDepth;
  float nearest = samples > 0.0 ? min(previous_passes.x, seen) : seen;
  float farthest = samples > 0.0 ? max(previous_passes.w, seen) : seen;
  imageStore(accum_passes, pixel, vec4(nearest, mix(previous_passes.y, shadow, w), samples + 1.0, farthest));
  vec4 previous_moments = pc.accumulation_frame == 0 ? vec4(0.0) : imageLoad(accum_moments, pixel);
  vec4 moments = mix(previous_moments, sample_moments(color), w);
  moments.w = float(uint(previous_moments.w) | surface_bits(pixel, position));  // (the instances its samples saw)
  imageStore(accum_moments, pixel, moments);
}
