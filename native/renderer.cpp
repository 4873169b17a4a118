#include "renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_access.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "shadow_casters.h"
#include "vk/context.h"

namespace rtsdf {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// OpenGL clip space (y up, z in [-1, 1]) -> Vulkan's (y down, z in [0, 1]).
const glm::mat4 kGlToVulkan(1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 0.5f, 0, 0, 0, 0.5f, 1);

// Temporal reuse (shaders/temporal_resolve.comp): history is clipped to the
// new frame's neighbourhood mean +- this many standard deviations; where a
// moved caster's shadow may have moved it stands for at most this many
// samples; and a reprojected surface is the same one within this share of its depth.
constexpr float kTemporalClip = 1.25f;
constexpr float kMovedShadowSamples = 1.0f;  // (a moved shadow: mostly from this frame)
// Where a moved caster's shadow may have moved, history is clipped tighter
// (a reactive mask): the receiver stood still, so its history passes the
// depth test, and a penumbra's neighbourhood spans so wide a range that the
// usual clip left the shadow's trailing edge a pixel behind. Measured on the
// 12 bench scenes' playback (the frame as the mover arrives, against Cycles):
// 0.75 took animated from 1.26x its converged still error to 1.19x, tree
// 1.29x -> 1.18x, sphere_plane 1.87x -> 1.58x, character 1.11x -> 1.05x;
// large_small went 1.16x -> 1.23x; 0.5 lost more elsewhere (large_small
// 1.32x, cad_on_ground 1.21x) and flickered more.
constexpr float kMovedShadowClip = 0.75f;
constexpr float kReprojectedDepthTolerance = 0.01f;
// Up to this many instances seen by the camera, a playback step's region on
// screen takes each one's box apart (screen_region.h); beyond, one box
// holding them all.
constexpr size_t kSeparatelyBoundedInstances = 64;
// Adaptive sampling judges a pixel's samples from this many on (and half of
// its samples): fewer always agree, whatever lies in the pixel.
constexpr int kFewestSamplesJudged = 4;

// The sub-pixel jitter's reach in whole pixels: the pixel filter's jitter
// reaches filter_width pixels either way.
float jitter_reach(float filter_width) { return std::ceil(std::max(filter_width, 0.5f)); }

float halton(uint32_t index, uint32_t base) {
  float f = 1.0f, r = 0.0f;
  for (uint32_t i = index + 1; i > 0; i /= base) f /= float(base), r += f * float(i % base);
  return r;
}

// The shadow casters placed elsewhere since the last frame (`motions`, per
// instance: world_motions), for the temporal passes to follow their shadows
// (FrameData::shadow_movers; none where none or more than the frame holds
// moved), and the boxes of those that stayed (FrameData::still_casters).
void put_shadow_movers(const GpuScene& scene, const std::vector<glm::mat4>& motions, const std::vector<uint8_t>& deformed,
                       gpu::FrameData& frame) {
  frame.shadow_counts = glm::uvec4(0u);
  std::vector<uint32_t> moved, still;
  for (uint32_t i : scene.shadow_casters()) (motions[i] == glm::mat4(1.0f) ? still : moved).push_back(i);
  if (moved.empty() || moved.size() > gpu::kMaxShadowMovers) return;
  const Scene& placed = scene.scene();
  uint32_t movers = 0;
  for (uint32_t i : moved) {
    const Bounds box = placed.world_bounds({i}, scene.mesh_extents());
    if (box.is_empty()) continue;
    glm::vec4* words = &frame.shadow_movers[gpu::kShadowMoverWords * movers++];
    words[0] = glm::vec4(box.lo, deformed[i] ? 1.0f : 0.0f);
    words[1] = glm::vec4(box.hi, 0.0f);
    for (int row = 0; row < 3; ++row) words[2 + row] = glm::row(motions[i], row);
  }
  std::vector<Bounds> boxes;  // (each one's, or one holding them all where they are many)
  if (still.size() <= gpu::kMaxShadowMovers)
    for (uint32_t i : still) boxes.push_back(placed.world_bounds({i}, scene.mesh_extents()));
  else
    boxes.push_back(placed.world_bounds(still, scene.mesh_extents()));
  uint32_t stills = 0;
  for (const Bounds& box : boxes) {
    if (box.is_empty()) continue;
    frame.still_casters[2 * stills] = glm::vec4(box.lo, 0.0f);
    frame.still_casters[2 * stills++ + 1] = glm::vec4(box.hi, 0.0f);
  }
  frame.shadow_counts = glm::uvec4(movers, stills, 0u, 0u);
}

}  // namespace

float pixel_filter_offset(float u, float width) {
  if (width <= 0.0f) return u - 0.5f;
  const float span = 2.0f * width;
  // The window's integral from its left end to the phase v (0 to 2 pi).
  auto integral = [](float v) {
    return 0.35875f * v - 0.48829f * std::sin(v) + 0.14128f * 0.5f * std::sin(2.0f * v) -
           0.01168f / 3.0f * std::sin(3.0f * v);
  };
  const float two_pi = 6.28318531f, target = u * integral(two_pi);
  float lo = 0.0f, hi = two_pi;
  for (int i = 0; i < 32; ++i) {
    const float mid = 0.5f * (lo + hi);
    (integral(mid) < target ? lo : hi) = mid;
  }
  return (0.5f * (lo + hi) / two_pi - 0.5f) * span;
}

namespace {

template <typename T>
std::vector<T> read_plane(const vk::Context& context, const vk::Image& image, int channels) {
  vk::Buffer readback = vk::download_image(context, image, sizeof(float) * channels);
  std::vector<T> values(image.texel_count() * channels);
  std::memcpy(values.data(), readback.mapped(), values.size() * sizeof(T));
  return values;
}

// The names settings and Python give an enum's values.
template <typename Enum>
struct Named {
  Enum value;
  const char* name;
};

// (any table of entries with a `value` and a `name`: Named, MethodTraits)
template <typename Entry, size_t N>
auto parse_name(const Entry (&table)[N], const std::string& name, const char* what) -> decltype(table[0].value) {
  std::string known;
  for (const Entry& entry : table) {
    if (name == entry.name) return entry.value;
    known += std::string(known.empty() ? "" : ", ") + entry.name;
  }
  throw Error("unknown " + std::string(what) + " '" + name + "': use one of " + known);
}

template <typename Entry, size_t N>
const char* name_of(const Entry (&table)[N], decltype(table[0].value) value) {
  for (const Entry& entry : table)
    if (entry.value == value) return entry.name;
  return "unknown";
}

// What each shadow method builds and how the shading looks its visibility
// up: the one table a new method is registered in (its name, its fields or
// maps, its kVisibility* lookup). Only visibility differs between methods.
enum class Fields {
  None,         // no SDF: shadow maps, or rays through the BVHs
  PerMesh,      // one field per mesh in its object space (ObjectFields)
  WorldCoarse,  // the whole scene's coarse (jump-flooded, unsigned) SDF alone
  WorldFine,    // the whole scene's coarse and fine SDFs
};

struct MethodTraits {
  ShadowMethod value;  // the method
  const char* name;
  Fields fields;
  uint32_t visibility;      // gpu::kVisibility*: how shade.comp looks visibility up
  bool trace_everywhere;    // the fine SDF traced at every texel, no band (FineTraceSettings)
  bool exact_rays;          // takes Exact Rays where the field is unsure (kVisibilityHybrid)
  bool jittered_maps;       // the shadow maps move over each light's shape every frame
};

constexpr MethodTraits kMethods[] = {
    {ShadowMethod::Rtsdf, "rtsdf", Fields::PerMesh, gpu::kVisibilitySignedSdf, false, true, false},
    {ShadowMethod::RtsdfWorld, "rtsdf_world", Fields::WorldFine, gpu::kVisibilitySignedSdf, false, true, false},
    {ShadowMethod::RtOnly, "rt_only", Fields::WorldFine, gpu::kVisibilitySignedSdf, true, true, false},
    {ShadowMethod::JfaOnly, "jfa_only", Fields::WorldCoarse, gpu::kVisibilityUnsignedSdf, false, false, false},
    {ShadowMethod::CsmEvsm, "csm_evsm", Fields::None, gpu::kVisibilityShadowMaps, false, false, false},
    {ShadowMethod::CsmJitter, "csm_jitter", Fields::None, gpu::kVisibilityShadowMaps, false, false, true},
    {ShadowMethod::RayTraced, "raytraced", Fields::None, gpu::kVisibilityRayTraced, false, false, false},
};

const MethodTraits& traits(ShadowMethod method) {
  for (const MethodTraits& entry : kMethods)
    if (entry.value == method) return entry;
  throw Error("unregistered shadow method");
}
constexpr Named<FieldView> kFieldViewNames[] = {{FieldView::None, "none"},
                                                {FieldView::DistanceSlice, "distance_slice"},
                                                {FieldView::MarchSteps, "march_steps"},
                                                {FieldView::FieldResolution, "field_resolution"},
                                                {FieldView::ExactRays, "exact_rays"}};

// The whole scene's fine SDF (world space).
bool uses_fine_sdf(ShadowMethod method) { return traits(method).fields == Fields::WorldFine; }

bool uses_shadow_maps(ShadowMethod method) { return traits(method).visibility == gpu::kVisibilityShadowMaps; }

// csm_jitter's filter: a texel's width, for anti-aliasing only (the penumbra
// comes from the moving origin).
constexpr float kJitteredMapFilterTexels = 1.0f;

// `light` moved to the point of its disk that sample `index` of a uniform
// disk sequence picks: a sun's direction within its angular radius, a local
// light's position across its radius, facing `target`.
Light jittered_light(const Light& light, uint32_t index, glm::vec3 target) {
  // Concentric mapping of (Halton 5, 7) to the unit disk (Shirley and Chiu).
  const glm::vec2 u(2.0f * halton(index, 5) - 1.0f, 2.0f * halton(index, 7) - 1.0f);
  glm::vec2 disk(0.0f);
  if (u.x != 0.0f || u.y != 0.0f) {
    const float quarter = float(M_PI) / 4.0f;
    disk = std::abs(u.x) > std::abs(u.y) ? u.x * glm::vec2(std::cos(quarter * u.y / u.x), std::sin(quarter * u.y / u.x))
                                         : u.y * glm::vec2(std::sin(quarter * u.x / u.y), std::cos(quarter * u.x / u.y));
  }
  Light moved = light;
  const glm::vec3 axis = light.type == LightType::Sun ? glm::normalize(light.direction)
                         : glm::length(target - light.position) > 0.0f ? glm::normalize(target - light.position)
                                                                        : glm::vec3(0.0f, 0.0f, -1.0f);
  const glm::vec3 hint = std::abs(axis.z) < 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
  const glm::vec3 right = glm::normalize(glm::cross(axis, hint)), up = glm::cross(right, axis);
  const glm::vec3 offset = disk.x * right + disk.y * up;
  if (light.type == LightType::Sun)
    moved.direction = glm::normalize(axis + std::tan(0.5f * std::min(light.sun_angle, 3.0f)) * offset);
  else
    moved.position = light.position + light.radius * offset;
  moved.sun_angle = 0.0f, moved.radius = 0.0f;  // (each map is of one point of the light)
  return moved;
}

ObjectFieldSettings object_field_settings(const RenderSettings& settings, const FineTraceSettings& fine) {
  ObjectFieldSettings objects;
  objects.coarse_resolution = settings.coarse_resolution;
  objects.fine_resolution = settings.fine_resolution;
  objects.beta = settings.beta;
  objects.fine = fine;
  objects.updates = settings.sdf_updates;
  objects.keep_history = settings.keep_history;
  objects.grid_slack = settings.grid_slack;
  objects.budget_mb = settings.field_budget_mb;
  return objects;
}

}  // namespace

ShadowMethod parse_shadow_method(const std::string& name) { return parse_name(kMethods, name, "shadow method"); }
const char* shadow_method_name(ShadowMethod method) { return name_of(kMethods, method); }
FieldView parse_field_view(const std::string& name) { return parse_name(kFieldViewNames, name, "field view"); }
const char* field_view_name(FieldView view) { return name_of(kFieldViewNames, view); }

Renderer::Renderer(const vk::Context& context, std::shared_ptr<FieldCache> field_cache)
    : context_(context),
      coarse_(context),
      fine_(context),
      gbuffer_(context),
      shade_(context),
      temporal_(context),
      object_fields_(context, std::move(field_cache)),
      world_field_(context),
      shading_timer_(context, 8),  // (begin, gbuffer, keep, quad, shade, resolve, converged)
      march_(context) {}

void Renderer::validate(int width, int height, const RenderSettings& settings) const {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) + " is out of range (1 to 16384)");
  if (settings.samples < 1 || settings.samples > 4096) throw Error("samples must be 1 to 4096");
  if (!(settings.noise_threshold >= 0.0f && settings.noise_threshold <= 1.0f))
    throw Error("noise_threshold must be 0 (every sample) to 1");
  if (settings.history_samples < 0 || settings.history_samples > 4096)
    throw Error("history_samples must be 0 to 4096");
  if (!(settings.filter_width >= 0.0f && settings.filter_width <= 500.0f))
    throw Error("filter_width must be 0 to 500 pixels (Blender's Filter Size range)");
  if (settings.sdf_updates < 0 || settings.sdf_updates > 4096) throw Error("sdf_updates must be 0 (every frame) to 4096");
  if (!(settings.grid_slack >= 0.0f && settings.grid_slack <= 4.0f)) throw Error("grid_slack must be 0 to 4");
  if (settings.shadow_max_steps < 1 || settings.shadow_max_steps > 4096) throw Error("shadow_max_steps must be 1 to 4096");
  if (!(settings.shadow_epsilon > 0.0f) || !(settings.max_step > 0.0f))
    throw Error("shadow_epsilon and max_step must be positive");
  if (settings.shadow_map_size < 64 || settings.shadow_map_size > 4096) throw Error("shadow_map_size must be 64 to 4096");
  if (settings.exact_rays < 0 || settings.exact_rays > 64) throw Error("exact_rays must be 0 (none) to 64");
  if (settings.short_history_rays < 1 || settings.short_history_rays > 16)
    throw Error("short_history_rays must be 1 (as many as exact_rays) to 16");
  if (!(settings.field_budget_mb >= 1.0 && settings.field_budget_mb <= 1e7))
    throw Error("field_budget_mb must be 1 to 10^7 MiB");
}

void Renderer::place_world_field(const GridSpec& grid) {
  world_field_.set_layout(grid, coarse_grid_, scene_->bounds());
  world_field_packed_ = false;
  march_.place({{&world_field_, glm::mat4(1.0f)}});
  field_voxels_.assign(scene_->instances().size(), 0.0f);
  for (uint32_t i : scene_->shadow_casters()) field_voxels_[i] = grid.voxel_size;
}

void Renderer::pack_world_field(const vk::Image* fine, float band) {
  const uint64_t placed = world_field_.generation();
  const PackedField::Source source{&coarse_.distance(), fine, band, fine ? coarse_.beta_world() : 0.0f};
  PackedField::pack(context_, {{&world_field_, source, 0.25f}});  // (slack: the scene's field changes with every move)
  world_field_packed_ = true;
  if (world_field_.generation() != placed) march_.place({{&world_field_, glm::mat4(1.0f)}});
}

void Renderer::update_field_memory_stats(ShadowMethod method) {
  constexpr double kMiB = 1 << 20;
  if (traits(method).fields == Fields::PerMesh) {
    const ObjectFieldStats& objects = object_fields_.stats();
    stats_.field_mb = double(objects.bytes) / kMiB;
    stats_.field_peak_mb = double(objects.peak_bytes) / kMiB;
    stats_.field_dense_mb = double(objects.dense_bytes) / kMiB;
    stats_.stored_bricks = objects.stored_bricks;
    stats_.brick_count = objects.brick_count;
    stats_.per_field = objects.per_field;
    return;
  }
  const bool fine = uses_fine_sdf(method);
  stats_.field_mb = double(coarse_.bytes() + fine_.bytes() + world_field_.bytes()) / kMiB;
  stats_.field_peak_mb = std::max(stats_.field_peak_mb, stats_.field_mb);
  stats_.field_dense_mb =
      double(coarse_.bytes() + (fine ? fine_grid_.voxel_count() * (FineSdf::kBytesPerTexel + 4) : coarse_grid_.voxel_count() * 4)) / kMiB;
  stats_.stored_bricks = world_field_.stored_bricks();
  stats_.brick_count = world_field_.brick_count();
}

FineTraceSettings Renderer::fine_settings() const {
  FineTraceSettings fine = settings_.fine;
  if (traits(settings_.shadow_method).trace_everywhere) fine.trace_everywhere = true;
  fine.skip_converged = false;  // (the whole scene's field follows every change: the paper's rule)
  return fine;
}

void Renderer::rebuild_sdfs(GpuScene& scene, const RenderSettings& settings) {
  const bool had_casters = has_casters_;
  has_casters_ = !scene.shadow_casters().empty();
  fine_updates_ = 0;
  const GpuScene::Changes changes = scene.take_changes();
  last_changes_ = changes;
  changed_region_.reset();
  stats_ = {};
  scene_ = &scene;
  field_voxels_.assign(scene.instances().size(), 0.0f);
  const ShadowMethod method = settings.shadow_method;
  const Fields fields = traits(method).fields;
  // Another method's fields hold memory this one does not read.
  const bool world_field = has_casters_ && (fields == Fields::WorldCoarse || fields == Fields::WorldFine);
  if (fields != Fields::PerMesh) object_fields_.clear();
  if (!world_field) {
    world_field_.release();
    world_field_packed_ = false;
    coarse_.release();
  }
  if (!uses_fine_sdf(method)) fine_.release();
  if (!has_casters_ || fields == Fields::None) {
    // Nothing to march (shadow maps need no SDF): their casters are still told
    // apart from receivers (they look themselves up off their surface).
    march_.place({});
    if (uses_shadow_maps(method))
      for (uint32_t i : scene.shadow_casters()) field_voxels_[i] = 1.0f;
    if (traits(method).visibility == gpu::kVisibilityRayTraced && has_casters_)
      scene.ray_structures();  // (built now, not in a frame)
    return;
  }
  if (fields == Fields::PerMesh) {
    FineTraceSettings fine = settings.fine;
    object_fields_.sync(scene, object_field_settings(settings, fine), march_);
    field_voxels_ = object_fields_.instance_voxels();
    const ObjectFieldStats& objects = object_fields_.stats();
    stats_.fields = objects.fields;
    stats_.field_instances = objects.placed;
    stats_.fields_regenerated = objects.regenerated;
    stats_.fields_reused = objects.reused;
    stats_.fields_loaded = objects.loaded;
    update_field_memory_stats(method);
    stats_.resolution_scale = objects.resolution_scale;
    stats_.surface_limited = objects.surface_limited;
    stats_.skipped_degenerate = objects.skipped_degenerate;
    return;
  }
  // The whole scene's field, in world space.
  // A grid is kept only for history (viewport, persistent data): a final
  // render's grid must not depend on what was rendered before.
  const bool may_keep = had_casters && settings.keep_history && settings.coarse_resolution == settings_.coarse_resolution;
  coarse_grid_ = keep_or_fit_grid(may_keep ? &coarse_grid_ : nullptr, scene.bounds(), settings.coarse_resolution,
                                  settings.grid_slack);
  coarse_.build(scene, coarse_grid_, settings.beta);
  stats_.fields = stats_.field_instances = stats_.fields_regenerated = 1;
  if (uses_fine_sdf(method)) {
    fine_grid_ = FineSdf::fit(coarse_grid_, settings.fine_resolution);
    // (a new grid resets it anyway; another method's field is not history)
    if (!settings.keep_history || method != settings_.shadow_method) fine_.reset();
    // Kept history: the next update retraces only near what moved or
    // deformed (nothing, if no caster did), the rest is still converged.
    else if (!changes.everything) changed_region_ = changes.any ? changes.region : Bounds::empty();
    place_world_field(fine_grid_);
  } else {
    place_world_field(coarse_grid_);
    pack_world_field(nullptr, 0.0f);
  }
  update_field_memory_stats(method);
}

bool same_settings(const RenderSettings& a, const RenderSettings& b) {
  auto values = [](const RenderSettings& settings) {
    std::vector<double> out;
    visit_settings(settings, [&](const char*, const auto& value) { out.push_back(double(value)); });
    return out;
  };
  return a.shadow_method == b.shadow_method && a.field_view == b.field_view && a.keep_history == b.keep_history &&
         values(a) == values(b);
}

void Renderer::begin(GpuScene& scene, const Camera& camera, const std::vector<Light>& lights, glm::vec3 ambient,
                     int width, int height, const RenderSettings& settings, bool scene_changed) {
  validate(width, height, settings);
  // (the temporal pass inverts the projection: a degenerate camera would put NaNs in every reprojection)
  const double camera_determinant = glm::determinant(glm::dmat4(camera.projection) * glm::dmat4(camera.world_to_view));
  if (!std::isfinite(camera_determinant) || camera_determinant == 0.0)
    throw Error("camera: its view and projection must be finite and invertible");
  const std::vector<gpu::GpuLight> gpu_lights = to_gpu(lights);  // (checks the lights first)
  const Clock::time_point start = Clock::now();
  timings_ = {};

  // The SDFs hold only what can shadow something, on grids fitted to it.
  // Which instances those are depends on the geometry and the lights, not the
  // view: a camera move in the viewport skips the search over every vertex.
  const std::vector<uint32_t> casters_before = scene.shadow_casters();
  const bool same_lights = gpu_lights.size() == lights_.size() &&
                           std::memcmp(gpu_lights.data(), lights_.data(), gpu_lights.size() * sizeof(gpu::GpuLight)) == 0;
  same_lighting_ = same_lights && ambient == glm::vec3(frame_data_.ambient);
  if (scene_changed || scene_ != &scene || !same_lights) {
    scene.set_shadow_casters(find_shadow_casters(scene.scene(), scene.mesh_extents(), lights));
    sky_blockers_ = sky_blockers(scene.scene(), scene.mesh_extents(), scene.shadow_casters(), gpu::kMaxSkyBlockers);
  }
  if (scene_changed || scene_ != &scene || scene.shadow_casters() != casters_before ||
      settings.coarse_resolution != settings_.coarse_resolution ||
      settings.fine_resolution != settings_.fine_resolution || settings.beta != settings_.beta ||
      settings.shadow_method != settings_.shadow_method || settings.field_budget_mb != settings_.field_budget_mb ||
      frame_ == 0)
    rebuild_sdfs(scene, settings);  // (otherwise the SDFs, independent of the view, stay as they are)
  else
    stats_.fields_regenerated = stats_.fields_reused = stats_.fields_loaded = 0, stats_.traced_texels = stats_.last_frame_traced_texels = 0;
  // History shows what these settings draw: another method or field view draws something else.
  const bool same_look = settings.shadow_method == settings_.shadow_method && settings.field_view == settings_.field_view &&
                         settings.field_view_height == settings_.field_view_height;
  scene_ = &scene;
  settings_ = settings;
  timings_.coarse_ms = ms_since(start);

  light_count_ = int(gpu_lights.size());
  lights_ = gpu_lights;
  light_buffer_ = vk::upload_buffer(context_, gpu_lights.data(), gpu_lights.size() * sizeof(gpu::GpuLight),
                                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  if (!frame_buffer_.handle())
    frame_buffer_ = vk::Buffer(context_, sizeof(gpu::FrameData), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                               vk::Buffer::Access::HostVisible);
  gbuffer_.resize(width, height);
  temporal_.resize(glm::ivec2(width, height));
  shade_.resize(glm::ivec2(width, height), light_count_);
  // History: the accumulation so far, if it drew this scene at this size.
  has_history_ = settings.temporal_reuse && same_look && frame_ > 0 && accum_.color.handle() && width == width_ &&
                 height == height_ && drawn_scene_id_ == scene.id() &&
                 drawn_transforms_.size() == scene.instances().size();
  const bool size_changed = width != width_ || height != height_ || !accum_.color.handle();
  if (size_changed || (settings.temporal_reuse && !history_.color.handle())) {
    const VkImageUsageFlags usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                      VK_IMAGE_USAGE_TRANSFER_DST_BIT;  // (a playback step copies history)
    std::vector<Accumulation*> accumulations = {&accum_};
    if (settings.temporal_reuse) accumulations.insert(accumulations.end(), {&history_, &resolved_});
    for (Accumulation* accumulation : accumulations)
      for (vk::Image* plane : {&accumulation->color, &accumulation->passes, &accumulation->moments}) {
        *plane = vk::Image::plane(context_, width, height, VK_FORMAT_R32G32B32A32_SFLOAT, usage);
        vk::make_general(context_, {plane});
      }
  }
  if (has_history_) std::swap(history_, accum_);
  width_ = width;
  height_ = height;

  const glm::mat4 view_to_world = glm::inverse(camera.world_to_view);
  frame_data_ = {};
  frame_data_.camera_position = glm::vec4(glm::vec3(view_to_world[3]), camera.orthographic ? 1.0f : 0.0f);
  frame_data_.camera_forward = glm::vec4(-glm::normalize(glm::vec3(view_to_world[2])), 0.0f);
  frame_data_.ambient = glm::vec4(ambient, float(sky_blockers_.size()));
  for (size_t i = 0; i < sky_blockers_.size(); ++i) {
    frame_data_.sky_blockers[2 * i] = glm::vec4(sky_blockers_[i].lo, 0.0f);
    frame_data_.sky_blockers[2 * i + 1] = glm::vec4(sky_blockers_[i].hi, 0.0f);
  }
  world_to_clip_ = kGlToVulkan * camera.projection * camera.world_to_view;
  // Motion since the last accumulation: its camera, and each instance's transform then.
  frame_data_.steady_world_to_clip = world_to_clip_;
  const glm::dmat4 clip_to_world = glm::inverse(glm::dmat4(world_to_clip_));
  frame_data_.steady_clip_to_world = glm::mat4(clip_to_world);
  const gpu::FrameData& drawn = has_history_ ? drawn_frame_ : frame_data_;
  frame_data_.previous_world_to_clip = has_history_ ? drawn.steady_world_to_clip : world_to_clip_;
  frame_data_.steady_clip_to_previous_clip =
      frame_data_.previous_world_to_clip == world_to_clip_
          ? glm::mat4(1.0f)
          : glm::mat4(glm::dmat4(frame_data_.previous_world_to_clip) * clip_to_world);
  camera_stayed_ = frame_data_.steady_clip_to_previous_clip == glm::mat4(1.0f);
  frame_data_.previous_camera_position = drawn.camera_position;
  frame_data_.previous_camera_forward = drawn.camera_forward;
  std::vector<glm::mat4> transforms;
  for (const Instance& instance : scene.instances()) transforms.push_back(instance.object_to_world);
  instance_motions_ = world_motions(has_history_ ? drawn_transforms_ : transforms, transforms);
  // The instances whose mesh deformed since the last begin(): their
  // vertices' own motion too (GpuScene::previous_positions).
  const std::vector<uint8_t> deformed_meshes = scene.take_deformations();
  instance_deformed_.assign(scene.instances().size(), 0);
  if (has_history_)
    for (size_t i = 0; i < instance_deformed_.size(); ++i) {
      const uint32_t mesh = scene.instances()[i].mesh;
      instance_deformed_[i] = mesh < deformed_meshes.size() ? deformed_meshes[mesh] : 0;
    }
  put_shadow_movers(scene, instance_motions_, instance_deformed_, frame_data_);
  for (size_t i = 0; i < instance_motions_.size(); ++i)  // (the history bits of all that moved or deformed: shared.h)
    if (instance_motions_[i] != glm::mat4(1.0f) || instance_deformed_[i])
      frame_data_.shadow_counts.z |= 1u << (i % gpu::kHistoryBits);
  if (has_history_ && scene_changed && last_changes_) {
    auto put = [](const Bounds& box, glm::vec4& lo, glm::vec4& hi) {
      lo = glm::vec4(box.lo, 1.0f), hi = glm::vec4(box.hi, 1.0f);
    };
    // What moved among the casters (their shadows moved with them): all of it
    // when the casters themselves were swapped.
    if (last_changes_->any || last_changes_->everything)
      put(last_changes_->everything ? scene.bounds() : last_changes_->region, frame_data_.changed_lo,
          frame_data_.changed_hi);
    // What moved on screen, casting shadows or not (a silhouette's history may hold it).
    if (last_changes_->any_moved) put(last_changes_->moved, frame_data_.moved_lo, frame_data_.moved_hi);
    // Each one's own box within those two, where they are few (BoxesApart).
    auto put_apart = [&](const BoxesApart& apart, glm::vec4* boxes, uint32_t& count) {
      count = 0;
      if (last_changes_->everything || apart.many) return;
      for (const auto& [instance, box] : apart.boxes) put(box, boxes[2 * count], boxes[2 * count + 1]), ++count;
    };
    put_apart(last_changes_->casters, frame_data_.changed_casters, frame_data_.boxes_apart.x);
    put_apart(last_changes_->instances, frame_data_.moved_instances, frame_data_.boxes_apart.y);
  }
  const glm::ivec2 size(width, height);
  change_on_screen_ = TileMask(size);
  if (has_history_ && camera_stayed_ && settings.changed_region_only) {  // (else no step is bounded by it)
    const GpuScene::Changes& pending = scene.pending_changes();
    const bool untold = !scene_changed && (pending.everything || pending.any || pending.any_moved ||
                                           drawn_transforms_ != transforms);  // (no box says where)
    // (the casters swapped: the shadows of those that left are in no box)
    const bool casters_swapped = scene_changed && last_changes_ && last_changes_->everything;
    if (untold || casters_swapped) {
      change_on_screen_ = TileMask::whole(size);
    } else if (frame_data_.changed_lo.w != 0.0f || frame_data_.moved_lo.w != 0.0f) {
      std::vector<uint32_t> seen;  // (no surface lies outside these)
      for (uint32_t i = 0; i < scene.instances().size(); ++i)
        if (scene.instances()[i].visible_to_camera) seen.push_back(i);
      // Each one's box, or one box holding them all where they are many
      // (each box is a pass over the tiles it reaches).
      std::vector<Bounds> boxes;
      if (seen.size() <= kSeparatelyBoundedInstances)
        for (uint32_t i : seen) boxes.push_back(scene.scene().world_bounds({i}, scene.mesh_extents()));
      else
        boxes.push_back(scene.scene().world_bounds(seen, scene.mesh_extents()));
      change_on_screen_ = change_on_screen(frame_data_, gpu_lights, boxes, size, jitter_reach(settings.filter_width));
    }
  }
  drawn_scene_id_ = scene.id();
  drawn_transforms_ = std::move(transforms);

  // Visibility: the fields the march reads, or the shadow maps. Distances
  // along the march are in voxels of the field nearest each sample.
  const MethodTraits& method = traits(settings.shadow_method);
  push_ = {};
  push_.visibility_mode = method.visibility;
  push_.field_instances = march_.instance_count();
  push_.max_march_steps = uint32_t(settings.shadow_max_steps);
  push_.shadow_epsilon = settings.shadow_epsilon;
  push_.max_step = settings.max_step;
  // A light's march starts half a voxel out: the receiver's own shell is escaped beyond it, and a wall
  // met at a corner within a whole voxel was never sampled (a seam of light ran up the corner). The
  // sky's cones start a whole voxel out: they are wide and many run near the horizon, and nearer the
  // receiver their first samples met its own shell (a moving character's ground speckled from frame
  // to frame).
  push_.receiver_clearance = 0.5f;
  push_.sky_receiver_clearance = 1.0f;
  push_.field_reach = settings.max_step * march_.largest_voxel();
  push_.caster_offset = 0.25f;
  push_.field_view = uint32_t(settings.field_view);
  push_.field_view_height = settings.field_view_height;
  if (method.exact_rays && settings.exact_rays > 0 && has_casters_) {
    push_.visibility_mode = gpu::kVisibilityHybrid;
    push_.exact_rays = uint32_t(settings.exact_rays);
    push_.short_history_rays = uint32_t(settings.short_history_rays);
    scene.ray_structures();  // (built now, not in a frame)
  }
  if (method.visibility == gpu::kVisibilityUnsignedSdf) {
    // The unsigned field's surfaces are shells epsilon + beta thick: a
    // caster's march starts outside its own shell (with a voxel to spare
    // for the flood's quantization), or its lit side would shadow itself.
    push_.caster_offset = settings.shadow_epsilon + settings.beta + 1.0f;
  }
  if (method.visibility == gpu::kVisibilityShadowMaps) {
    if (!shadow_maps_) shadow_maps_ = std::make_unique<ShadowMapPass>(context_);
    // Jittered maps are fitted again every frame, to the light's next point.
    const float filter = method.jittered_maps ? kJitteredMapFilterTexels : 0.0f;
    shadow_map_lights_ = lights;
    shadow_map_camera_ = camera;
    shadow_maps_->setup(scene, lights, camera.world_to_view, camera.projection, settings.shadow_map_size, filter);
    push_.shadow_map_tile_texels = uint32_t(shadow_maps_->tile_size());
    push_.caster_offset = 0.0f;
    push_.shadow_map_offset = 1.0f;  // a texel off their own depth in the maps
    push_.evsm_exponents = glm::vec2(ShadowMapPass::kPositiveExponent, ShadowMapPass::kNegativeExponent);
    push_.light_bleeding_reduction = ShadowMapPass::kLightBleedingReduction;
    push_.map_filter_texels = filter;
  }
  if (method.visibility == gpu::kVisibilityRayTraced) push_.caster_offset = 0.0f;  // (rays start off the surface on their own)
  shadow_map_renders_ = 0;
  history_frames_ = has_history_ ? frame_ : 0;
  frame_ = 0;
  listed_.reset();
  stats_.sampled_share = 0.0;
  if (!has_history_) sequence_ = 0;
  timings_.total_ms = ms_since(start);
}

bool Renderer::visibility_due(int done) const {
  return has_casters_ && (settings_.sdf_updates == 0 || done < settings_.sdf_updates);
}

bool Renderer::visibility_settled() const {
  if (refining()) return false;
  if (uses_fine_sdf(settings_.shadow_method) && visibility_due(fine_updates_)) return false;
  // csm_jitter's maps are rendered from another point of each light every
  // frame, and its penumbra is their mean: a pixel whose first frames' maps
  // all saw it lit may lie in the penumbra of the points still to come (in
  // bench/run's quick rows, judged after 4 of 6 frames, grazing's shadow RMSE
  // went from 0.0096 to 0.0110).
  if (traits(settings_.shadow_method).jittered_maps) return false;
  return !uses_shadow_maps(settings_.shadow_method) || !visibility_due(shadow_map_renders_);
}

void Renderer::add_frame() {
  if (!scene_) throw Error("add_frame: call begin() first");
  if (all_converged() && !refining()) return;  // (no frame is left to draw)
  const Clock::time_point start = Clock::now();
  stats_.last_frame_traced_texels = 0;
  if (uses_fine_sdf(settings_.shadow_method) && visibility_due(fine_updates_)) {
    fine_.update(*scene_, coarse_, fine_grid_, fine_settings(), changed_region_ ? &*changed_region_ : nullptr);
    pack_world_field(&fine_.distance(), fine_settings().band_world(coarse_grid_.voxel_size));
    update_field_memory_stats(settings_.shadow_method);
    changed_region_.reset();  // later updates go on converging everywhere
    fine_updates_++;
    stats_.last_frame_traced_texels = fine_.read_traced_texels();
  } else if (traits(settings_.shadow_method).fields == Fields::PerMesh && has_casters_) {
    // Each field refines in its own first updates; still fields cost nothing.
    object_fields_.refine(*scene_, march_);
    update_field_memory_stats(settings_.shadow_method);
    stats_.last_frame_traced_texels = object_fields_.stats().traced_texels;
  }
  stats_.traced_texels += stats_.last_frame_traced_texels;
  timings_.fine_ms += ms_since(start);
  const Clock::time_point maps = Clock::now();
  const MethodTraits& method = traits(settings_.shadow_method);
  if (method.jittered_maps && has_casters_) {
    // Every frame from another point of each light (sdf_updates does not stop it: the frames' mean is the penumbra).
    std::vector<Light> moved;
    const glm::vec3 target = 0.5f * (scene_->bounds().lo + scene_->bounds().hi);
    for (const Light& light : shadow_map_lights_) moved.push_back(jittered_light(light, sequence_, target));
    shadow_maps_->setup(*scene_, moved, shadow_map_camera_.world_to_view, shadow_map_camera_.projection,
                        settings_.shadow_map_size, kJitteredMapFilterTexels);
    context_.submit_and_wait([&](VkCommandBuffer cmd) { shadow_maps_->record(cmd, *scene_); });
  } else if (uses_shadow_maps(settings_.shadow_method) && visibility_due(shadow_map_renders_)) {
    context_.submit_and_wait([&](VkCommandBuffer cmd) { shadow_maps_->record(cmd, *scene_); });
    shadow_map_renders_++;
  }
  timings_.shadow_map_ms += ms_since(maps);

  if (all_converged()) {
    // (a field refines, every pixel has settled: nothing is left to shade)
    stats_.drawn_share = 0.0;
    timings_.total_ms += ms_since(start);
    frame_++;
    sequence_++;
    return;
  }
  const Clock::time_point shading = Clock::now();
  // Sub-pixel jitter (Halton 2,3 through the pixel filter) for anti-aliasing, averaged over frames; but
  // a playback frame of the viewport is drawn at the pixel centres: the first after objects moved under a
  // still camera, whose history was itself such a frame or a converged image. Where the move dropped
  // history (a moved shadow, an uncovered background, the mover's outline) that frame's one sample is
  // what the pixel shows, and a sample at the centre lies nearer the filtered pixel than a jittered one
  // (which pays off only averaged). Not under a moving camera: every pixel takes this frame's sample, and
  // a centred one each step would leave edges unfiltered for as long as it moves. Not in an animation
  // render (history_samples set): its frames end after their few samples, and the same centre each frame
  // would weigh in every frame written as several samples; the viewport's accumulation goes on after
  // playback with jittered frames, and history's count is capped, so the centred ones fade.
  const bool playback_frame =
      settings_.history_samples == 0 && (history_frames_ == 1 || history_frames_ >= settings_.samples);
  const bool centred = has_history_ && frame_ == 0 && camera_stayed_ && playback_frame &&
                       (frame_data_.changed_lo.w != 0.0f || frame_data_.moved_lo.w != 0.0f);
  const glm::vec2 jitter = centred ? glm::vec2(0.0f)
                                   : glm::vec2(pixel_filter_offset(halton(sequence_, 2), settings_.filter_width),
                                               pixel_filter_offset(halton(sequence_, 3), settings_.filter_width));
  const glm::mat4 shift = glm::translate(glm::mat4(1.0f), glm::vec3(2.0f * jitter.x / float(width_),
                                                                   2.0f * jitter.y / float(height_), 0.0f));
  frame_data_.world_to_clip = shift * world_to_clip_;
  std::memcpy(frame_buffer_.mapped(), &frame_data_, sizeof frame_data_);
  push_.image_size = glm::ivec2(width_, height_);
  push_.light_count = light_count_;
  push_.accumulation_frame = frame_;
  push_.sequence = sequence_;
  const ShadowMapPass* shadow_maps = uses_shadow_maps(settings_.shadow_method) ? shadow_maps_.get() : nullptr;
  const bool traces_rays =
      push_.visibility_mode == gpu::kVisibilityRayTraced || push_.visibility_mode == gpu::kVisibilityHybrid;
  const GpuScene::RayStructures* rays = traces_rays && has_casters_ ? &scene_->ray_structures() : nullptr;
  // Temporal reuse, in the first frame after a change: history is kept
  // before the shading where it stands whatever the new sample (with the
  // camera and the lighting as they were; otherwise no pixel would be),
  // and resolved with the sample after it.
  const bool resolves = has_history_ && frame_ == 0;
  const bool keeps = resolves && same_lighting_ && camera_stayed_;
  // After a keep pass or a converged test in the frame before: the tiles it listed alone.
  const bool listed_before = listed_.has_value();  // (none in a first frame: begin() dropped it)
  push_.listed_tiles = keeps || listed_before ? 1u : 0u;
  // Adaptive sampling: the converged test after this frame, from the frame
  // that completes half the samples on (every pixel has taken those), and at
  // least kFewestSamplesJudged (one or two samples always agree), where the
  // next frame sees the visibility as this one.
  const int judged_from = std::max((settings_.samples + 1) / 2, kFewestSamplesJudged);
  const bool tests_convergence = settings_.noise_threshold > 0.0f && frame_ + 1 >= judged_from &&
                                 frame_ + 1 < settings_.samples && visibility_settled();
  const gpu::TemporalPush temporal = resolves ? temporal_push() : gpu::TemporalPush{};
  const TemporalImages temporal_images{accum_, history_, resolved_};
  auto compute_barrier = [](VkCommandBuffer cmd) {
    vk::memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  };
  // A playback step that keeps history draws the region its change can
  // reach and the pixels not yet settled before it; nothing outside reads
  // this frame's G-buffer, and history stands there as it was. Only a step
  // drawn at the pixel centres: a jittered sample at a still silhouette may
  // see a surface its history never saw anywhere on screen (the jitter went
  // on to an offset the still frames did not take), and such a pixel is
  // shaded anew.
  const glm::ivec2 size(width_, height_);
  TileMask frame_region = TileMask::whole(size);  // (the tiles the frame works on)
  PixelRect drawn = PixelRect::whole(size);
  if (keeps && centred && settings_.changed_region_only) {
    TileMask unsettled = change_on_screen_;
    unsettled.add(unsettled_.image_size() == size ? unsettled_ : TileMask::whole(size));
    frame_region = temporal_.keep_region(unsettled);
    drawn = temporal_.drawn_region(unsettled);
  }
  // The frames after a keep pass or a converged test: the tiles they listed
  // (a tile left out has settled, and stays so in this accumulation).
  if (listed_before) {
    frame_region = *listed_;
    drawn = temporal_.drawn_region(*listed_);
  }
  stats_.drawn_share = frame_region.share();
  stats_.sampled_share += stats_.drawn_share / double(settings_.samples);
  context_.submit_and_wait([&](VkCommandBuffer cmd) {
    shading_timer_.begin(cmd);
    gbuffer_.record(cmd, *scene_, frame_buffer_, field_voxels_, instance_motions_, instance_deformed_, drawn);
    shading_timer_.mark(cmd, "gbuffer");
    if (keeps) {
      temporal_.record_keep(cmd, gbuffer_, temporal_images, frame_buffer_, light_buffer_, temporal, frame_region);
      compute_barrier(cmd);
      shading_timer_.mark(cmd, "keep");
    }
    const bool march_sky = push_.visibility_mode != gpu::kVisibilityShadowMaps &&
                           glm::dot(glm::vec3(frame_data_.ambient), glm::vec3(frame_data_.ambient)) > 0.0f;
    const bool share_lights = settings_.quick_first_frame && frame_ == 0;
    const KeptTiles kept_tiles = temporal_.kept_tiles();
    shade_.record(cmd, {gbuffer_, march_, shadow_maps, rays, light_buffer_, frame_buffer_, &kept_tiles},
                  {accum_.color, accum_.passes, accum_.moments},
                  march_sky, share_lights, push_, &shading_timer_);
    shading_timer_.mark(cmd, "shade");
    if (resolves) {
      compute_barrier(cmd);
      temporal_.record(cmd, gbuffer_, temporal_images, frame_buffer_, light_buffer_, temporal, keeps);
      shading_timer_.mark(cmd, "temporal");
    }
    if (tests_convergence) {
      compute_barrier(cmd);
      temporal_.record_converged(cmd, resolves ? resolved_ : accum_, temporal_push(), frame_region);
      shading_timer_.mark(cmd, "converged");
    }
  });
  if (resolves) std::swap(accum_, resolved_);
  // What may not have settled now: where the keep pass did not keep; every
  // pixel after a frame that reprojected all of history or had none; none
  // once the frames since have drawn each pixel's full samples (a pixel
  // shaded anew from no history has them after history_samples frames).
  stats_.short_history_share = keeps ? temporal_.short_history_share() : 0.0;
  // The tiles still short of samples are the next frames': those the keep
  // pass did not keep (a kept pixel is settled, with its full samples),
  // until a converged test finds which still are.
  if (keeps || tests_convergence) {
    listed_ = temporal_.unsettled_tiles();
    // (and the tiles left of and above them: history is read a texel right and below too)
    unsettled_ = listed_->spread([](int x) { return glm::ivec2(x - 1, x); }, [](int y) { return glm::ivec2(y - 1, y); });
  } else if (frame_ == 0) {
    unsettled_ = TileMask::whole(size);
  }
  if (frame_ + 1 >= temporal_push().history_samples) unsettled_ = TileMask(size);
  drawn_frame_ = frame_data_;
  timings_.shade_ms += ms_since(shading);
  for (const vk::GpuTimer::Span& span : shading_timer_.read()) {
    (span.label == "gbuffer" ? timings_.gbuffer_gpu_ms : timings_.shade_gpu_ms) += span.ms;
    if (span.label == "quad") timings_.quad_gpu_ms += span.ms;
    if (span.label == "keep" || span.label == "temporal" || span.label == "converged") timings_.temporal_gpu_ms += span.ms;
    if (span.label == "keep") timings_.keep_gpu_ms += span.ms;
  }
  timings_.total_ms += ms_since(start);
  frame_++;
  sequence_++;
}

gpu::TemporalPush Renderer::temporal_push() const {
  gpu::TemporalPush temporal{};
  temporal.image_size = glm::ivec2(width_, height_);
  temporal.light_count = light_count_;
  temporal.history_samples = settings_.history_samples > 0 ? settings_.history_samples : settings_.samples;
  temporal.clip = kTemporalClip;
  temporal.moved_shadow_clip = kMovedShadowClip;
  temporal.moved_shadow_samples = kMovedShadowSamples;
  temporal.depth_tolerance = kReprojectedDepthTolerance;
  temporal.jitter_reach = jitter_reach(settings_.filter_width);
  temporal.same_lighting = same_lighting_ ? 1u : 0u;
  temporal.noise_threshold = settings_.noise_threshold;
  return temporal;
}

namespace {
std::vector<glm::vec4> read_vec4_plane(const vk::Context& context, const vk::Image& image) {
  const std::vector<float> values = read_plane<float>(context, image, 4);
  std::vector<glm::vec4> texels(values.size() / 4);
  for (size_t i = 0; i < texels.size(); ++i)
    texels[i] = glm::vec4(values[4 * i], values[4 * i + 1], values[4 * i + 2], values[4 * i + 3]);
  return texels;
}
}  // namespace

std::vector<glm::vec4> Renderer::read_motion() const { return read_vec4_plane(context_, gbuffer_.motion()); }

std::vector<glm::vec4> Renderer::read_sample_moments() const {
  if (!accum_.moments.handle()) return {};
  return read_vec4_plane(context_, accum_.moments);
}

RenderOutput Renderer::read(bool passes) const {
  RenderOutput out;
  out.width = width_;
  out.height = height_;
  out.timings = timings_;
  out.stats = stats_;
  out.samples_done = frame_;
  if (!accum_.color.handle()) return out;
  // Both images in one submission, through the kept staging buffer: the
  // viewport's read of a 633x385 image took 5.4 ms (median of 60 converged
  // redraws) with a new buffer and a submission for each.
  const std::vector<VkDeviceSize> at =
      passes ? vk::download_images(context_, {&accum_.color, &accum_.passes}, 4 * sizeof(float), readback_)
             : vk::download_images(context_, {&accum_.color}, 4 * sizeof(float), readback_);
  const uint8_t* staged = static_cast<const uint8_t*>(readback_.mapped());
  const size_t pixels = size_t(width_) * height_;
  out.combined.resize(4 * pixels);
  std::memcpy(out.combined.data(), staged + at[0], out.combined.size() * sizeof(float));
  if (passes) {
    const float* all = reinterpret_cast<const float*>(staged + at[1]);
    out.depth.resize(pixels);
    out.shadow.resize(pixels);
    out.samples.resize(pixels);
    double sum = 0.0;
    size_t covered = 0;
    for (size_t i = 0; i < pixels; ++i) {
      out.depth[i] = all[4 * i], out.shadow[i] = all[4 * i + 1], out.samples[i] = all[4 * i + 2];
      if (out.combined[4 * i + 3] > 0.0f) sum += out.samples[i], ++covered;
    }
    out.effective_samples = covered ? sum / double(covered) : double(frame_);
  }
  return out;
}

RenderOutput Renderer::render(GpuScene& scene, const Camera& camera, const std::vector<Light>& lights,
                              glm::vec3 ambient, int width, int height, const RenderSettings& settings,
                              const Progress& progress) {
  const Clock::time_point start = Clock::now();
  begin(scene, camera, lights, ambient, width, height, settings, /*scene_changed=*/true);
  for (int sample = 0; sample < settings.samples && !all_converged(); ++sample) {
    add_frame();
    if (progress && !progress(sample + 1, settings.samples)) break;
  }
  RenderOutput out = read();
  out.timings.total_ms = ms_since(start);
  return out;
}

}  // namespace rtsdf
