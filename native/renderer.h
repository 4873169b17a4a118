#pragma once
// The whole RTSDF frame: coarse SDF -> fine SDF -> G-buffer -> shading with
// SDF soft shadows, averaged over accumulation frames. Baselines share the
// G-buffer and the shading and differ only in visibility (ShadowMethod).
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coarse_sdf.h"
#include "fine_sdf.h"
#include "lights.h"
#include "march_fields.h"
#include "object_fields.h"
#include "passes/gbuffer.h"
#include "passes/shade.h"
#include "passes/temporal.h"
#include "passes/shadow_map.h"

namespace rtsdf {

struct Camera {
  glm::mat4 world_to_view{1.0f};
  glm::mat4 projection{1.0f};  // OpenGL convention (as Blender gives it): y up, z in [-1, 1]
  bool orthographic = false;
};

// Fine-SDF settings for shading. The band is 3 coarse voxels, not 2: beyond it
// the field is the coarse c = distance - beta, which reads up to beta + half a
// coarse voxel low, and penumbra tails reaching that far came out too dark
// (RendererTest.SpherePenumbraMatchesAnalyticWidth: a dip to 0.83 at d = 2).
inline FineTraceSettings shading_fine_settings() {
  FineTraceSettings settings;
  settings.trace_band = 2.0f;
  settings.skip_converged = true;  // (the object fields of meshes that do not deform)
  settings.near_surface_only = true;  // (the renderer's fields are packed for the march)
  return settings;
}

// Where shadows come from. Settings and Python name them rtsdf, rtsdf_world,
// rt_only, jfa_only, csm_evsm, csm_jitter and raytraced.
enum class ShadowMethod {
  Rtsdf,       // the paper's fields (coarse by jump flooding, fine ray traced in a band around surfaces), one per
               // mesh in its own space, shared by its instances (object_fields.h)
  RtsdfWorld,  // the paper as published: one field of the whole scene in world space, rebuilt after any change
  RtOnly,   // the whole scene's fine SDF ray traced at every texel of its grid (no band), every frame
  JfaOnly,  // no fine SDF: the march reads the coarse (jump-flooded, unsigned) SDF
  CsmEvsm,  // no SDF: cascaded shadow maps filtered as EVSM (the paper's comparison), as wide as the penumbra a
            // blocker search finds (PCSS)
  CsmJitter,  // no SDF: the same shadow maps, sharp, their origin moved to another point of each light every
              // frame (EEVEE's soft shadows): the frames' mean converges towards the true penumbra
  RayTraced,  // no SDF: a ray through the BVHs towards a random point of each light (and two over the sky's
              // hemisphere) per frame, averaging to the exact visibility over the samples: the reference that
              // tells the fields' error from the shading's
};
// Throws rtsdf::Error for an unknown name.
ShadowMethod parse_shadow_method(const std::string& name);
const char* shadow_method_name(ShadowMethod method);

// What the image shows: the shaded scene, or a view of the distance fields
// in its place (shaders/field_views.glsl.h). Settings and Python name them
// none, distance_slice, march_steps, field_resolution and exact_rays.
enum class FieldView {
  None = gpu::kDebugNone,
  DistanceSlice = gpu::kDebugDistanceSlice,      // the fields' distance on the plane z = field_view_height
  MarchSteps = gpu::kDebugMarchSteps,            // the zero level sphere-traced from the camera, by its steps
  FieldResolution = gpu::kDebugFieldResolution,  // each surface by its field's voxel against the pixel's size
  ExactRays = gpu::kDebugExactRays,              // the shaded image, the pixels the hybrid traced marked
};
// Throws rtsdf::Error for an unknown name.
FieldView parse_field_view(const std::string& name);
const char* field_view_name(FieldView view);

struct RenderSettings {
  ShadowMethod shadow_method = ShadowMethod::Rtsdf;
  int coarse_resolution = 64;
  float beta = 0.5f;             // coarse voxels
  int fine_resolution = 128;
  FineTraceSettings fine = shading_fine_settings();
  float shadow_epsilon = 1.0f;   // voxels of the field marched: fine (jfa_only: coarse); the paper: at least one
  int shadow_max_steps = 96;
  float max_step = 4.0f;         // voxels of the field marched, as shadow_epsilon
  int shadow_map_size = 1024;    // csm_evsm, csm_jitter: texels per side of each cascade (and spot view, cube face)
  FieldView field_view = FieldView::None;
  float field_view_height = 0.0f;  // world z of FieldView::DistanceSlice's plane
  // Signed-field methods (rtsdf, rtsdf_world, rt_only): where the march cannot
  // tell lit from shadowed with shadow_epsilon to spare (penumbrae, contact,
  // occluders thinner than the field resolves), this many rays per light and
  // frame through the casters' BVHs decide instead (0: the field's cone
  // estimate everywhere, as in the paper).
  int exact_rays = 0;
  // ... and in the first frame after a change, this many times as many
  // where history may stand for one sample or none (a moved shadow on a
  // surface that stays, an uncovered one): there the frame shown is mostly
  // that sample. 1: as in any frame (on scenes whose exact rays are many and
  // costly, such as dense CAD, the faster playback).
  int short_history_rays = 4;
  int samples = 16;              // accumulation frames (sub-pixel and shadow-origin jitter each)
  // Adaptive sampling: once half the frames are drawn (4 at least) and the
  // fields and shadow maps no longer change, a tile of pixels whose samples
  // agree (one sample's standard deviation below this share of each pixel's
  // brightness) takes no more; the frames after shade only the tiles still
  // short, and an accumulation whose every tile has converged ends early
  // (shaders/temporal_converged.comp). 0: every pixel takes every sample.
  float noise_threshold = 0.03f;
  // Pixel filter: Blackman-Harris, this wide in pixels (Blender's Filter Size,
  // Cycles' default filter and width), sampled by each frame's sub-pixel
  // jitter so that accumulated frames converge to the filtered image, as
  // Cycles' do. 0: a box over the pixel.
  float filter_width = 1.5f;
  // Fine-SDF updates per render, one in each of the first accumulation frames
  // (0: every frame). A static frame's field is near converged after a few;
  // the later frames only refine the anti-aliasing and the shadow jitter.
  // csm_evsm renders its shadow maps by the same rule.
  int sdf_updates = 0;
  // Room left around the shadow casters when a grid is fitted, as a share of
  // their extent: while they stay inside it (and fill it well enough), the
  // grid stays, and with it the fine SDF's history. 0 fits them tightly.
  float grid_slack = 0.0f;
  // Keep the fine SDF of the previous render (same grid) and go on accumulating
  // it, as the paper does frame to frame; the decay forgets what moved.
  bool keep_history = false;
  // rtsdf: device memory for all meshes' fields, in MiB (resolutions are
  // lowered alike to fit it).
  double field_budget_mb = 1024.0;
  // SDF methods: the first accumulation frame marches the lights' shadows at
  // one pixel of each 2x2 quad, and the pixels on the same surface take them
  // from there (see ShadePass): the viewport's frame after a change at about
  // half the shading cost. The frames after it march every pixel, so an
  // image accumulated over many frames barely differs.
  bool quick_first_frame = false;
  // Temporal reuse (the viewport during playback and edits): a begin() after
  // a change carries the accumulation so far into the new one where it still
  // shows the same surface (passes/temporal.h), standing for up to `samples`
  // samples. Off: every begin() starts from nothing (final renders, unless an
  // animation render opts in).
  bool temporal_reuse = false;
  // The most samples reprojected history stands for (0: `samples`). An
  // animation render that draws few samples a frame lets history stand for
  // the rest.
  int history_samples = 0;
  // A playback step (temporal reuse under the same camera and lights, drawn
  // at the pixel centres after something moved) draws
  // its G-buffer and keeps history over the region its change can reach on
  // screen (screen_region.h) and the pixels left unsettled before it; the
  // rest of the image is history as it was. Off: over the whole image (to
  // compare: the colours come out the same).
  bool changed_region_only = true;
};

// The settings a caller names by key (the Python module's dicts), one list
// for reading them, reporting their defaults and comparing them. (The
// shadow method and field view go by their names; keep_history is the
// viewport's and the final render's own.)
template <class Settings, class Visit>
void visit_settings(Settings& settings, Visit&& visit) {
  visit("shadow_map_size", settings.shadow_map_size);
  visit("field_view_height", settings.field_view_height);
  visit("exact_rays", settings.exact_rays);
  visit("short_history_rays", settings.short_history_rays);
  visit("coarse_resolution", settings.coarse_resolution);
  visit("fine_resolution", settings.fine_resolution);
  visit("beta", settings.beta);
  visit("trace_band", settings.fine.trace_band);
  visit("decay", settings.fine.decay);
  visit("rays_per_texel", settings.fine.rays_per_texel);
  visit("interleave", settings.fine.interleave);
  visit("shadow_epsilon", settings.shadow_epsilon);
  visit("shadow_max_steps", settings.shadow_max_steps);
  visit("max_step", settings.max_step);
  visit("samples", settings.samples);
  visit("noise_threshold", settings.noise_threshold);
  visit("filter_width", settings.filter_width);
  visit("sdf_updates", settings.sdf_updates);
  visit("grid_slack", settings.grid_slack);
  visit("field_budget_mb", settings.field_budget_mb);
  visit("quick_first_frame", settings.quick_first_frame);
  visit("temporal_reuse", settings.temporal_reuse);
  visit("history_samples", settings.history_samples);
  visit("changed_region_only", settings.changed_region_only);
}

// Whether two settings draw the same: every visited setting, the method,
// the field view and keep_history.
bool same_settings(const RenderSettings& a, const RenderSettings& b);

// What the SDF methods did, for the stats a user sees.
struct RenderStats {
  int fields = 0;               // distance fields held (rtsdf: one per geometry that casts shadows)
  int field_instances = 0;      // placed in the scene (rtsdf: instances share their mesh's field)
  int fields_regenerated = 0;   // fields (re)built by begin(): voxelized and jump flooded
  int fields_reused = 0;        // rtsdf: fields begin() took refined from another render (FieldCache)
  int fields_loaded = 0;        // ... of which from disk (the FieldCache's FieldStore)
  uint64_t traced_texels = 0;   // fine texels ray traced since begin()
  uint64_t last_frame_traced_texels = 0;
  double field_mb = 0.0;        // device memory of the fields now (packed, and SDFs still kept for updates)
  double field_peak_mb = 0.0;   // the most they held since begin() (rtsdf: what field_budget_mb bounds)
  double field_dense_mb = 0.0;  // what dense grids of the same voxels would take, for comparison
  uint64_t stored_bricks = 0;   // bricks of fine texels the packed fields hold (see PackedField)
  uint64_t brick_count = 0;     // bricks their fine grids span
  std::vector<FieldMemory> per_field;  // rtsdf: each mesh's field
  float resolution_scale = 1;   // rtsdf: below 1, resolutions lowered to fit field_budget_mb
  bool surface_limited = false;  // ... to fit the fields' surface voxel budget (ObjectFieldSettings), not the memory
  int skipped_degenerate = 0;   // rtsdf: instances a scale flattens to nothing, left out of the fields
  // The share of the image the last frame drew (the tiles its temporal keep
  // pass tested, or the converged test left to shade; its G-buffer drew a
  // rectangle around them): below 1 in a playback step that drew its changed
  // region alone, and in the frames after pixels converged.
  double drawn_share = 0.0;
  // The frames' shading work over what every pixel sampled in every frame
  // would have been (the drawn shares summed, over the frames asked for):
  // below 1 where adaptive sampling stopped tiles or the whole accumulation.
  double sampled_share = 0.0;
  // The share of the image whose history the last frame's keep pass found
  // may stand for one sample or none (a moved shadow on a still surface, a
  // disocclusion): there its exact rays, if any, were short_history_rays
  // times as many (shaders/shared.h). 0 where no keep pass ran.
  double short_history_share = 0.0;
};

struct RenderTimings {
  // Wall time: coarse_ms is begin()'s (the coarse SDF's build, if any), fine_ms
  // the fine-SDF updates, shadow_map_ms the shadow maps' renders and blurs
  // (csm_evsm), shade_ms the G-buffer and shading.
  double coarse_ms = 0, fine_ms = 0, shade_ms = 0, total_ms = 0;
  double shadow_map_ms = 0;
  // Device time of shade_ms's passes (0 where the device has no timestamps):
  // the G-buffer, the quarter-rate visibility pass (quad_gpu_ms: the world
  // light, and the lights in a quick first frame), the temporal reuse after a
  // change (temporal_gpu_ms; keep_gpu_ms its keep pass, before the shading)
  // and the shading (shade_gpu_ms, which includes quad_gpu_ms and
  // temporal_gpu_ms).
  double gbuffer_gpu_ms = 0, quad_gpu_ms = 0, temporal_gpu_ms = 0, keep_gpu_ms = 0, shade_gpu_ms = 0;
};

struct RenderOutput {
  int width = 0, height = 0;
  std::vector<float> combined;  // RGBA, rows top to bottom; alpha = coverage
  std::vector<float> depth;     // distance along the view axis; 1e10 where nothing is hit
  std::vector<float> shadow;    // direct light with shadows / without (1 where unlit or empty)
  std::vector<float> samples;   // samples each pixel's mean stands for (history's included; with the passes)
  // Their mean over the pixels that show a surface: the effective sample
  // count of this frame (the frames since begin(), more with temporal reuse).
  double effective_samples = 0.0;
  RenderTimings timings;
  RenderStats stats;
  int samples_done = 0;  // fewer than asked when stopped through Progress, or when every tile converged
};

// The offset from the pixel centre (in pixels, along one axis) left of which a
// share u of the pixel filter's weight lies: uniform u in [0, 1) gives
// offsets distributed as the filter (RenderSettings::filter_width).
// Blackman-Harris as Cycles uses it: the window spans twice the filter width.
// Width 0: a box over the pixel.
float pixel_filter_offset(float u, float width);

class Renderer {
 public:
  // `field_cache` (may be null): refined fields shared with the device's other renderers (field_cache.h).
  explicit Renderer(const vk::Context& context, std::shared_ptr<FieldCache> field_cache = nullptr);
  // Called after each accumulation frame with (frames done, frames in all);
  // returning false stops the render there (the output holds what was done).
  using Progress = std::function<bool(int, int)>;

  // Renders `scene` (its SDFs are rebuilt: call again after any change). Sets
  // the scene's shadow casters from find_shadow_casters(scene, lights).
  // Throws rtsdf::Error for bad sizes or settings.
  RenderOutput render(GpuScene& scene, const Camera& camera, const std::vector<Light>& lights, glm::vec3 ambient,
                      int width, int height, const RenderSettings& settings, const Progress& progress = {});

  // Progressive rendering, as the viewport does it: begin() starts a new
  // accumulation (rebuilding the SDFs when `scene_changed`, or when the
  // shadow casters or resolutions changed), then each add_frame() adds one
  // accumulation frame: a fine-SDF update while settings.sdf_updates allows,
  // the G-buffer and the shading. `scene` must stay alive and unchanged
  // between begin() and the add_frame() calls.
  void begin(GpuScene& scene, const Camera& camera, const std::vector<Light>& lights, glm::vec3 ambient, int width,
             int height, const RenderSettings& settings, bool scene_changed);
  void add_frame();
  int frames() const { return frame_; }
  // Whether the accumulation is done: its samples drawn, or every tile
  // converged (RenderSettings::noise_threshold), and no field refining.
  bool converged() const { return !refining() && (frame_ >= settings_.samples || all_converged()); }
  // Whether some object-space field is still refining: a viewport keeps
  // drawing frames until it is not, even with its samples in.
  bool refining() const {
    return settings_.shadow_method == ShadowMethod::Rtsdf && has_casters_ && object_fields_.refining();
  }
  // Wall times since begin().
  const RenderTimings& timings() const { return timings_; }
  const RenderStats& stats() const { return stats_; }
  // The accumulated image so far; the depth and shadow passes only if asked.
  RenderOutput read(bool passes = true) const;
  // The last frame's G-buffer motion per pixel (rows top to bottom): xy = where
  // its surface point was in the last accumulation's frame, from where it is
  // now (normalized device coordinates), z = its depth from that camera, w =
  // 1 where known (see shaders/gbuffer_fragment.glsl.h); outside the region
  // a playback step drew (RenderSettings::changed_region_only), an earlier
  // frame's. For inspection and tests.
  std::vector<glm::vec4> read_motion() const;
  // The accumulation's running second moments per pixel (rows top to
  // bottom): the mean over its samples of the Combined colour's Y, Co and
  // Cg squared (shaders/sample_moments.glsl.h).
  // The temporal resolve judges a still pixel's noise by them. For tests.
  std::vector<glm::vec4> read_sample_moments() const;
  // The whole scene's fine SDF as the last frame left it (rtsdf_world,
  // rt_only; its grid is empty before the first update).
  const FineSdf& fine_sdf() const { return fine_; }
  // The fields the march reads: with rtsdf, mesh `mesh`'s own (in its
  // object space); with the whole-scene methods, the scene's (world space).
  // Null if there is none yet.
  const PackedField* mesh_field(uint32_t mesh) const { return object_fields_.packed_field(mesh); }
  const PackedField* world_field() const { return world_field_packed_ ? &world_field_ : nullptr; }
  // csm_evsm's shadow maps as begin() fitted them (null before its first use).
  const ShadowMapPass* shadow_maps() const { return shadow_maps_.get(); }

 private:
  void validate(int width, int height, const RenderSettings& settings) const;
  void rebuild_sdfs(GpuScene& scene, const RenderSettings& settings);
  // Places the whole scene's field (world space, on `grid` with coarse_grid_
  // as its far field) as the one field marched.
  void place_world_field(const GridSpec& grid);
  // Packs the whole scene's fine SDF `fine` (null: the coarse SDF alone) into that field.
  // `band`: the fine SDF's trace band (FineTraceSettings::band_world).
  void pack_world_field(const vk::Image* fine, float band);
  // The fields' memory and bricks under `method` into stats_.
  void update_field_memory_stats(ShadowMethod method);
  FineTraceSettings fine_settings() const;
  // The visibility's per-frame work, in the first sdf_updates frames (0:
  // every frame), `done` of them done.
  bool visibility_due(int done) const;
  // Whether the frames from the next on see the visibility as this one did:
  // no field refines or updates, and no shadow map is rendered again (the
  // jittered maps of csm_jitter never are). Adaptive sampling waits for it.
  bool visibility_settled() const;
  // The temporal passes' constants for this accumulation's settings and lights.
  gpu::TemporalPush temporal_push() const;

  const vk::Context& context_;
  CoarseSdf coarse_;
  FineSdf fine_;
  GBufferPass gbuffer_;
  ShadePass shade_;
  TemporalPass temporal_;
  std::unique_ptr<ShadowMapPass> shadow_maps_;  // made on first use of csm_evsm
  ObjectFields object_fields_;
  PackedField world_field_;            // the whole scene's, packed (the whole-scene methods)
  vk::GpuTimer shading_timer_;
  bool world_field_packed_ = false;
  MarchFields march_;                  // the fields the shading marches
  std::vector<float> field_voxels_;    // per instance: its field's world voxel (0: in none)

  // The accumulation begin() set up.
  GpuScene* scene_ = nullptr;
  RenderSettings settings_;
  GridSpec coarse_grid_, fine_grid_;
  bool has_casters_ = false;
  int width_ = 0, height_ = 0;
  int frame_ = 0;
  int history_frames_ = 0;  // the frames the accumulation that history holds drew (0: no history)
  // The frame's index in the jitter sequences (pixel filter, shadow origins,
  // light samples): frame_ in a fresh accumulation, counted on where history
  // carries over, or every frame after a change would repeat sample 0.
  uint32_t sequence_ = 0;
  int fine_updates_ = 0;        // since the SDFs were rebuilt
  std::optional<Bounds> changed_region_;  // for the first fine update after a local change
  int shadow_map_renders_ = 0;  // since begin() (the maps follow the camera)
  RenderTimings timings_;
  RenderStats stats_;
  gpu::FrameData frame_data_{};
  gpu::ShadePush push_{};
  glm::mat4 world_to_clip_{1.0f};
  int light_count_ = 0;
  std::vector<gpu::GpuLight> lights_;  // as last uploaded: a view-only change keeps the shadow casters
  std::vector<Light> shadow_map_lights_;  // csm_jitter: the lights whose points its maps move over
  Camera shadow_map_camera_;              // csm_jitter: the camera its maps are fitted to
  std::vector<Bounds> sky_blockers_;   // found with the shadow casters
  vk::Buffer light_buffer_;
  vk::Buffer frame_buffer_;
  Accumulation accum_;
  // Where read() copies the image to, kept from read to read (a viewport reads every redraw).
  mutable vk::Buffer readback_;

  // Temporal reuse: the last accumulation (history) while the first frame
  // after a change is resolved into resolved_, which then becomes accum_.
  Accumulation history_, resolved_;
  bool has_history_ = false;      // this accumulation's first frame reprojects history
  bool camera_stayed_ = false;    // the camera is where history saw it (or there is no history)
  bool same_lighting_ = false;    // the lights and the world are as history saw them (settled pixels may stay)
  uint64_t drawn_scene_id_ = 0;   // the scene, transforms and camera the last accumulation drew
  std::vector<glm::mat4> drawn_transforms_;
  gpu::FrameData drawn_frame_{};
  std::vector<glm::mat4> instance_motions_;  // per instance, for the G-buffer's motion (world_motions)
  std::vector<uint8_t> instance_deformed_;   // per instance: its mesh deformed since the last begin() (ditto)
  std::optional<GpuScene::Changes> last_changes_;  // taken by the last rebuild_sdfs
  // Playback steps draw these alone (RenderSettings::changed_region_only):
  // where this accumulation's change can reach on screen (begin() finds it),
  // and the pixels of the accumulation that may not have settled (full
  // samples, as still as history was): those the last keep pass did not
  // keep, until the frames after it have drawn every pixel's samples.
  TileMask change_on_screen_;
  TileMask unsettled_;
  // The tiles the last keep pass or converged test of this accumulation
  // listed as still short of samples: the frames after it shade those
  // alone; none listed, the accumulation is done.
  std::optional<TileMask> listed_;
  bool all_converged() const { return listed_ && listed_->is_empty(); }
};

}  // namespace rtsdf
