// rtsdf_native: the native core seen from Python (and Blender's Python).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <type_traits>
#include <cstring>
#include <memory>

#include "coarse_sdf.h"
#include "exr_output.h"
#include "field_cache.h"
#include "field_store.h"
#include "kept_scene.h"
#include "renderer.h"
#include "viewport.h"
#include "version.h"
#include "vk/context.h"

namespace py = pybind11;

namespace {

py::dict describe(const rtsdf::vk::DeviceInfo& info) {
  py::dict d;
  d["name"] = info.name;
  d["type"] = info.type;
  d["api_version"] = info.api_version;
  d["driver"] = info.driver;
  return d;
}

rtsdf::Mesh mesh_from_arrays(py::array_t<float, py::array::c_style | py::array::forcecast> positions,
                             py::array_t<uint32_t, py::array::c_style | py::array::forcecast> indices) {
  if (positions.ndim() != 2 || positions.shape(1) != 3) throw rtsdf::Error("positions must have shape (N, 3)");
  if (indices.ndim() != 2 || indices.shape(1) != 3) throw rtsdf::Error("indices must have shape (M, 3)");
  rtsdf::Mesh mesh;
  mesh.name = "mesh";
  const float* p = positions.data();
  for (py::ssize_t i = 0; i < positions.shape(0); ++i) mesh.positions.emplace_back(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
  mesh.indices.assign(indices.data(), indices.data() + indices.size());
  return mesh;
}

py::dict coarse_sdf(py::array_t<float, py::array::c_style | py::array::forcecast> positions,
                    py::array_t<uint32_t, py::array::c_style | py::array::forcecast> indices, int coarse_resolution,
                    float beta) {
  rtsdf::Scene scene = rtsdf::single_mesh_scene(mesh_from_arrays(positions, indices));
  scene.validate();
  rtsdf::GridSpec grid = rtsdf::fit_grid(scene.world_bounds(), coarse_resolution);
  std::vector<float> distance;
  rtsdf::CoarseSdfTimings timings;
  std::string device;
  {
    py::gil_scoped_release release;
    rtsdf::vk::Context context;
    rtsdf::CoarseSdf coarse(context);
    rtsdf::GpuScene gpu_scene(context, scene);
    coarse.build(gpu_scene, grid, beta);
    distance = coarse.read_distance();
    timings = coarse.timings();
    device = context.info().name;
  }
  py::array_t<float> field({grid.dims.z, grid.dims.y, grid.dims.x});
  std::copy(distance.begin(), distance.end(), field.mutable_data());
  py::dict result;
  result["distance"] = field;  // indexed [z, y, x], world units
  result["origin"] = py::make_tuple(grid.origin.x, grid.origin.y, grid.origin.z);
  result["voxel_size"] = grid.voxel_size;
  result["dims"] = py::make_tuple(grid.dims.x, grid.dims.y, grid.dims.z);
  result["beta"] = beta * grid.voxel_size;
  result["device"] = device;
  result["ms"] = py::dict(py::arg("voxelize") = timings.voxelize_ms, py::arg("jump_flood") = timings.jump_flood_ms);
  return result;
}

template <typename T>
T get(const py::dict& d, const char* key, T fallback) {
  return d.contains(key) ? d[key].cast<T>() : fallback;
}

glm::vec3 vec3_of(const py::handle& h) {
  auto v = h.cast<std::vector<float>>();
  if (v.size() != 3) throw rtsdf::Error("expected 3 numbers");
  return {v[0], v[1], v[2]};
}

// A 4x4 matrix given row by row (as Blender's Matrix and numpy print it).
glm::mat4 mat4_of(const py::handle& h) {
  auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(h);
  if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4) throw rtsdf::Error("expected a 4x4 matrix");
  glm::mat4 m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = a.at(r, c);
  return m;
}

rtsdf::LightType light_type(const std::string& name) {
  if (name == "SUN") return rtsdf::LightType::Sun;
  if (name == "POINT") return rtsdf::LightType::Point;
  if (name == "SPOT") return rtsdf::LightType::Spot;
  if (name == "AREA") return rtsdf::LightType::Area;
  throw rtsdf::Error("unknown light type '" + name + "'");
}

// A mesh as sync's "meshes" entries give it: positions, indices, optional name, normals, per-triangle
// material slots ("materials"), UVs and colours.
rtsdf::Mesh mesh_of(const py::dict& d) {
  rtsdf::Mesh mesh = mesh_from_arrays(
      d["positions"].cast<py::array_t<float, py::array::c_style | py::array::forcecast>>(),
      d["indices"].cast<py::array_t<uint32_t, py::array::c_style | py::array::forcecast>>());
  mesh.name = get<std::string>(d, "name", "mesh");
  if (d.contains("normals")) {
    auto normals = d["normals"].cast<py::array_t<float, py::array::c_style | py::array::forcecast>>();
    if (normals.ndim() != 2 || normals.shape(1) != 3) throw rtsdf::Error("normals must have shape (N, 3)");
    for (py::ssize_t i = 0; i < normals.shape(0); ++i)
      mesh.normals.emplace_back(normals.at(i, 0), normals.at(i, 1), normals.at(i, 2));
  }
  if (d.contains("materials")) {
    auto slots = d["materials"].cast<py::array_t<uint32_t, py::array::c_style | py::array::forcecast>>();
    mesh.materials.assign(slots.data(), slots.data() + slots.size());
  }
  if (d.contains("uvs")) {
    auto uvs = d["uvs"].cast<py::array_t<float, py::array::c_style | py::array::forcecast>>();
    if (uvs.ndim() != 2 || uvs.shape(1) != 2) throw rtsdf::Error("uvs must have shape (N, 2)");
    for (py::ssize_t i = 0; i < uvs.shape(0); ++i) mesh.uvs.emplace_back(uvs.at(i, 0), uvs.at(i, 1));
  }
  if (d.contains("colors")) {
    auto colors = d["colors"].cast<py::array_t<float, py::array::c_style | py::array::forcecast>>();
    if (colors.ndim() != 2 || colors.shape(1) < 3) throw rtsdf::Error("colors must have shape (N, 3) or (N, 4)");
    for (py::ssize_t i = 0; i < colors.shape(0); ++i)
      mesh.colors.emplace_back(colors.at(i, 0), colors.at(i, 1), colors.at(i, 2));
  }
  return mesh;
}

// An image as sync's "textures" entries give it: name, and pixels (H, W, 4) uint8, rows from the bottom, sRGB-encoded.
rtsdf::Texture texture_of(const py::dict& d) {
  rtsdf::Texture texture;
  texture.name = get<std::string>(d, "name", "image");
  auto pixels = d["pixels"].cast<py::array_t<uint8_t, py::array::c_style | py::array::forcecast>>();
  if (pixels.ndim() != 3 || pixels.shape(2) != 4) throw rtsdf::Error("image '" + texture.name + "' must have shape (H, W, 4)");
  texture.height = int(pixels.shape(0));
  texture.width = int(pixels.shape(1));
  texture.texels.resize(size_t(pixels.shape(0)) * size_t(pixels.shape(1)));
  std::memcpy(texture.texels.data(), pixels.data(), texture.texels.size() * sizeof(uint32_t));  // (RGBA bytes: R lowest)
  return texture;
}

rtsdf::Scene scene_of(const py::dict& scene_desc) {
  rtsdf::Scene scene;
  for (const py::handle& mesh_desc : scene_desc["meshes"].cast<py::list>())
    scene.meshes.push_back(mesh_of(mesh_desc.cast<py::dict>()));
  for (const py::handle& instance_desc : scene_desc["instances"].cast<py::list>()) {
    py::dict d = instance_desc.cast<py::dict>();
    rtsdf::Instance instance;
    instance.mesh = d["mesh"].cast<uint32_t>();
    instance.object_to_world = mat4_of(d["matrix"]);
    if (d.contains("color")) instance.base_color = vec3_of(d["color"]);
    if (d.contains("materials"))
      for (const py::handle& slot : d["materials"].cast<py::list>()) {
        py::dict m = slot.cast<py::dict>();
        instance.materials.push_back({vec3_of(m["color"]), get<int>(m, "texture", -1), get<bool>(m, "vertex_color", false)});
      }
    instance.casts_shadow = get<bool>(d, "casts_shadow", true);
    instance.visible_to_camera = get<bool>(d, "visible_camera", true);
    instance.holdout = get<bool>(d, "holdout", false);
    scene.instances.push_back(instance);
  }
  if (scene_desc.contains("textures"))
    for (const py::handle& texture : scene_desc["textures"].cast<py::list>()) scene.textures.push_back(texture_of(texture.cast<py::dict>()));
  return scene;
}

std::vector<rtsdf::Light> lights_of(const py::list& lights_desc) {
  std::vector<rtsdf::Light> lights;
  for (const py::handle& light_desc : lights_desc) {
    py::dict d = light_desc.cast<py::dict>();
    rtsdf::Light light;
    light.type = light_type(d["type"].cast<std::string>());
    light.position = vec3_of(d["position"]);
    light.direction = vec3_of(d["direction"]);
    light.color = vec3_of(d["color"]);
    light.energy = d["energy"].cast<float>();
    light.sun_angle = get<float>(d, "angle", 0.0f);
    light.radius = get<float>(d, "radius", 0.0f);
    light.casts_shadow = get<bool>(d, "casts_shadow", true);
    light.spot_size = get<float>(d, "spot_size", 0.0f);
    light.spot_blend = get<float>(d, "spot_blend", 0.0f);
    lights.push_back(light);
  }
  return lights;
}

rtsdf::Camera camera_of(const py::dict& camera_desc) {
  rtsdf::Camera camera;
  camera.world_to_view = mat4_of(camera_desc["world_to_view"]);
  camera.projection = mat4_of(camera_desc["projection"]);
  camera.orthographic = get<bool>(camera_desc, "orthographic", false);
  return camera;
}

// The settings a dict names (rtsdf::visit_settings' keys, shadow_method and
// field_view), the others as in `defaults`.
rtsdf::RenderSettings settings_of(const py::dict& settings_desc, rtsdf::RenderSettings defaults = {}) {
  rtsdf::RenderSettings settings = defaults;
  // "rtsdf", "rtsdf_world", "rt_only", "jfa_only", "csm_evsm", "csm_jitter" or "raytraced"; anything else is an rtsdf.Error.
  settings.shadow_method = rtsdf::parse_shadow_method(
      get<std::string>(settings_desc, "shadow_method", rtsdf::shadow_method_name(settings.shadow_method)));
  // "none", "distance_slice", "march_steps", "field_resolution" or "exact_rays"; anything else is an rtsdf.Error.
  settings.field_view = rtsdf::parse_field_view(
      get<std::string>(settings_desc, "field_view", rtsdf::field_view_name(settings.field_view)));
  rtsdf::visit_settings(settings, [&](const char* key, auto& value) {
    value = get<std::remove_reference_t<decltype(value)>>(settings_desc, key, value);
  });
  return settings;
}

py::dict default_settings() {
  rtsdf::RenderSettings settings;
  py::dict defaults;
  defaults["shadow_method"] = rtsdf::shadow_method_name(settings.shadow_method);
  defaults["field_view"] = rtsdf::field_view_name(settings.field_view);
  rtsdf::visit_settings(settings, [&](const char* key, auto& value) { defaults[key] = value; });
  return defaults;
}

py::dict timings_of(const rtsdf::RenderTimings& t) {
  return py::dict(py::arg("sdf") = t.coarse_ms, py::arg("fine") = t.fine_ms, py::arg("shadow_map") = t.shadow_map_ms,
                  py::arg("shade") = t.shade_ms, py::arg("total") = t.total_ms,
                  py::arg("gbuffer_gpu") = t.gbuffer_gpu_ms, py::arg("quad_gpu") = t.quad_gpu_ms,
                  py::arg("temporal_gpu") = t.temporal_gpu_ms, py::arg("keep_gpu") = t.keep_gpu_ms,
                  py::arg("shade_gpu") = t.shade_gpu_ms);
}

// What the SDF methods did (see rtsdf::RenderStats).
py::dict stats_of(const rtsdf::RenderStats& s) {
  py::dict stats;
  stats["fields"] = s.fields;
  stats["field_instances"] = s.field_instances;
  stats["fields_regenerated"] = s.fields_regenerated;
  stats["fields_reused"] = s.fields_reused;
  stats["fields_loaded"] = s.fields_loaded;
  stats["traced_texels"] = s.traced_texels;
  stats["last_frame_traced_texels"] = s.last_frame_traced_texels;
  stats["field_mb"] = s.field_mb;
  stats["field_peak_mb"] = s.field_peak_mb;
  stats["field_dense_mb"] = s.field_dense_mb;
  stats["stored_bricks"] = s.stored_bricks;
  stats["brick_count"] = s.brick_count;
  py::list per_field;
  for (const rtsdf::FieldMemory& f : s.per_field)
    per_field.append(py::dict(py::arg("mesh") = f.mesh, py::arg("mb") = double(f.bytes) / (1 << 20),
                              py::arg("stored_bricks") = f.stored_bricks, py::arg("brick_count") = f.brick_count,
                              py::arg("voxel_size") = f.voxel_size, py::arg("detail") = f.detail));
  stats["per_field"] = per_field;
  stats["resolution_scale"] = s.resolution_scale;
  stats["resolution_limited_by"] = s.resolution_scale < 1.0f ? (s.surface_limited ? "surface" : "memory") : "";
  stats["skipped_degenerate"] = s.skipped_degenerate;
  stats["drawn_share"] = s.drawn_share;
  stats["sampled_share"] = s.sampled_share;
  stats["short_history_share"] = s.short_history_share;
  return stats;
}

py::array_t<float> image_of(const std::vector<float>& values, int height, int width, int channels) {
  py::array_t<float> image = channels == 1 ? py::array_t<float>({height, width}) : py::array_t<float>({height, width, channels});
  std::copy(values.begin(), values.end(), image.mutable_data());
  return image;
}

// A viewport (rtsdf::Viewport) on a session's device: dicts in, dicts out.
class Viewport {
 public:
  Viewport(std::shared_ptr<rtsdf::vk::Context> context, std::shared_ptr<rtsdf::FieldCache> field_cache)
      : context_(std::move(context)), viewport_(*context_, std::move(field_cache)) {}

  void sync(const py::dict& scene_desc) {
    rtsdf::Scene scene = scene_of(scene_desc);
    py::gil_scoped_release release;
    viewport_.sync(scene);
  }

  bool update(const py::dict& scene_desc) {
    rtsdf::Scene scene = scene_of(scene_desc);
    py::gil_scoped_release release;
    return viewport_.update(scene);
  }

  void set_transforms(const py::list& matrices) {
    std::vector<glm::mat4> transforms;
    for (const py::handle& m : matrices) transforms.push_back(mat4_of(m));
    py::gil_scoped_release release;
    viewport_.set_transforms(transforms);
  }

  void set_mesh(uint32_t mesh, py::array_t<float, py::array::c_style | py::array::forcecast> positions) {
    if (positions.ndim() != 2 || positions.shape(1) != 3) throw rtsdf::Error("positions must have shape (N, 3)");
    std::vector<glm::vec3> points;
    for (py::ssize_t i = 0; i < positions.shape(0); ++i)
      points.emplace_back(positions.at(i, 0), positions.at(i, 1), positions.at(i, 2));
    py::gil_scoped_release release;
    viewport_.set_mesh_positions(mesh, points);
  }

  void set_mesh_geometry(uint32_t mesh, const py::dict& mesh_desc) {
    rtsdf::Mesh geometry = mesh_of(mesh_desc);
    py::gil_scoped_release release;
    viewport_.set_mesh(mesh, std::move(geometry));
  }

  void restart() { viewport_.restart(); }

  py::dict draw(const py::dict& view_desc, const py::dict& settings_desc) {
    rtsdf::View view;
    view.lights = lights_of(view_desc["lights"].cast<py::list>());
    view.camera = camera_of(view_desc["camera"].cast<py::dict>());
    view.width = view_desc["width"].cast<int>();
    view.height = view_desc["height"].cast<int>();
    view.ambient = vec3_of(view_desc["ambient"]);
    const rtsdf::RenderSettings settings = settings_of(settings_desc, rtsdf::Viewport::default_settings());
    rtsdf::ViewportFrame frame;
    {
      py::gil_scoped_release release;
      frame = viewport_.draw(view, settings);
    }
    py::dict result;
    result["combined"] = image_of(frame.image.combined, view.height, view.width, 4);  // rows top to bottom
    result["frames"] = frame.image.samples_done;
    result["effective_samples"] = frame.effective_samples;
    // (with temporal reuse: the samples each pixel stands for, history's included)
    if (!frame.image.samples.empty()) result["samples"] = image_of(frame.image.samples, view.height, view.width, 1);
    result["converged"] = frame.converged;
    result["advanced"] = frame.advanced;
    result["draw_ms"] = py::dict(py::arg("begin") = frame.begin_ms, py::arg("frame") = frame.frame_ms,
                                 py::arg("read") = frame.read_ms);
    result["ms"] = timings_of(frame.image.timings);
    result["stats"] = stats_of(frame.image.stats);
    result["validation_messages"] = context_->validation_message_count();
    return result;
  }

  // The field the march reads, as the last draw left it, for inspection:
  // {space, origin, voxel_size, distance (z, y, x)}: mesh `mesh`'s own field
  // in its object space (rtsdf), else the whole scene's in world space; its
  // texels from the bricks near surfaces and the far field elsewhere (see
  // PackedField). None before the first fine-SDF update.
  py::object fine_sdf(uint32_t mesh) const {
    const rtsdf::PackedField* own = viewport_.renderer().mesh_field(mesh);
    const rtsdf::PackedField* field = own ? own : viewport_.renderer().world_field();
    if (!field) return py::none();
    const rtsdf::GridSpec grid = field->grid();
    std::vector<float> values;
    {
      py::gil_scoped_release release;
      values = field->read_texels();
    }
    py::array_t<float> distance({grid.dims.z, grid.dims.y, grid.dims.x});
    std::copy(values.begin(), values.end(), distance.mutable_data());
    return py::dict(py::arg("space") = own ? "object" : "world",
                    py::arg("origin") = py::make_tuple(grid.origin.x, grid.origin.y, grid.origin.z),
                    py::arg("voxel_size") = grid.voxel_size, py::arg("distance") = distance);
  }

 private:
  std::shared_ptr<rtsdf::vk::Context> context_;  // (declared first: destroyed last)
  rtsdf::Viewport viewport_;
};

// One Vulkan context kept between renders. Final renders keep their scene
// with Blender's persistent data; each viewport gets its own Viewport.
class Session {
 public:
  Session()
      : context_(std::make_shared<rtsdf::vk::Context>()),
        field_cache_(std::make_shared<rtsdf::FieldCache>(field_cache_capacity(*context_))),
        renderer_(*context_, field_cache_),
        kept_scene_(*context_) {}

  std::unique_ptr<Viewport> viewport() const { return std::make_unique<Viewport>(context_, field_cache_); }

  // Drops the refined fields kept for later renders (the next render of each mesh builds its field again).
  void forget_fields() { field_cache_->clear(); }
  py::dict kept_fields() const {
    py::dict out;
    out["count"] = field_cache_->size();
    out["mb"] = double(field_cache_->bytes()) / double(1 << 20);
    out["capacity_mb"] = double(field_cache_->capacity()) / double(1 << 20);
    return out;
  }

  static constexpr double kFieldStoreMinMb = 16.0, kFieldStoreMaxMb = double(1 << 20);
  // Keeps refined fields in `directory` too, at most capacity_mb of them, for
  // later processes; "" keeps them in memory only (the default).
  void set_field_store(const std::string& directory, double capacity_mb) {
    if (directory.empty()) {
      field_cache_->set_store(nullptr);
      return;
    }
    if (!(capacity_mb >= kFieldStoreMinMb) || !(capacity_mb <= kFieldStoreMaxMb))  // (the preference's range)
      throw rtsdf::Error("the field store's capacity_mb must be 16 to 1048576");
    const auto current = field_cache_->store();
    const size_t capacity = size_t(capacity_mb * double(1 << 20));
    if (current && current->directory() == directory && current->capacity() == capacity) return;
    field_cache_->set_store(std::make_shared<rtsdf::FieldStore>(directory, capacity));
  }
  py::object field_store() const {
    const auto store = field_cache_->store();
    if (!store) return py::none();
    const rtsdf::FieldStore::Stats stats = store->stats();
    py::dict out;
    out["directory"] = store->directory().string();
    out["capacity_mb"] = double(store->capacity()) / double(1 << 20);
    out["files"] = stats.files;
    out["mb"] = double(stats.bytes) / double(1 << 20);
    out["loaded"] = stats.loaded;
    out["saved"] = stats.saved;
    out["passed_over"] = stats.passed_over;
    out["failed_saves"] = stats.failed_saves;
    out["last_error"] = stats.last_error;
    return out;
  }

  int validation_messages() const { return context_->validation_message_count(); }

  std::string device() const { return context_->info().name; }

  // persistent: keep the device scene (uploads, BVHs), and with it the
  // fields and history, where its structure stays (KeptScene::update).
  py::dict render(const py::dict& scene_desc, const py::dict& settings_desc, const py::object& progress,
                  bool persistent) {
    rtsdf::Scene scene = scene_of(scene_desc);
    std::vector<rtsdf::Light> lights = lights_of(scene_desc["lights"].cast<py::list>());
    rtsdf::Camera camera = camera_of(scene_desc["camera"].cast<py::dict>());
    const int width = scene_desc["width"].cast<int>(), height = scene_desc["height"].cast<int>();
    const glm::vec3 ambient = vec3_of(scene_desc["ambient"]);
    rtsdf::RenderSettings settings = settings_of(settings_desc);

    // progress(done, total, preview) -> bool: False stops the render
    // (Blender's cancel); preview() reads the Combined image so far (rows top
    // to bottom), for a progressive display.
    rtsdf::Renderer::Progress report;
    if (!progress.is_none())
      report = [&progress, this, width, height](int done, int total) {
        py::gil_scoped_acquire acquire;
        py::cpp_function preview([this, width, height]() {
          rtsdf::RenderOutput partial;
          {
            py::gil_scoped_release release;
            partial = renderer_.read(/*passes=*/false);
          }
          return image_of(partial.combined, height, width, 4);
        });
        return progress(done, total, preview).cast<bool>();
      };
    settings.keep_history = persistent;
    rtsdf::RenderOutput out;
    bool reused = false;
    {
      py::gil_scoped_release release;
      if (!persistent) kept_scene_.clear();
      reused = kept_scene_.update(scene) != rtsdf::SceneUpdate::Uploaded;
      out = renderer_.render(kept_scene_.gpu(), camera, lights, ambient, width, height, settings, report);
      if (!persistent) kept_scene_.clear();
    }
    py::dict result;
    result["combined"] = image_of(out.combined, height, width, 4);  // rows top to bottom
    result["depth"] = image_of(out.depth, height, width, 1);
    result["shadow"] = image_of(out.shadow, height, width, 1);
    result["ms"] = timings_of(out.timings);
    result["stats"] = stats_of(out.stats);
    result["validation_messages"] = context_->validation_message_count();
    result["samples_done"] = out.samples_done;
    // (with temporal reuse, history's samples too)
    result["effective_samples"] = settings.temporal_reuse ? out.effective_samples : double(out.samples_done);
    result["scene_reused"] = reused;
    return result;
  }

 private:
  // Refined fields kept for the next renders: an eighth of the device's memory, at most 512 MiB.
  static size_t field_cache_capacity(const rtsdf::vk::Context& context) {
    return std::min<size_t>(size_t(512) << 20, context.device_local_heap_bytes() / 8);
  }

  std::shared_ptr<rtsdf::vk::Context> context_;
  std::shared_ptr<rtsdf::FieldCache> field_cache_;  // shared with its viewports
  rtsdf::Renderer renderer_;
  rtsdf::KeptScene kept_scene_;  // between persistent renders
};

}  // namespace

PYBIND11_MODULE(rtsdf_native, m) {
  m.doc() = "RTSDF native core: real-time signed distance fields on Vulkan";
  py::register_exception<rtsdf::Error>(m, "Error", PyExc_RuntimeError);
  m.attr("__version__") = rtsdf::kVersion;
  m.def("default_settings", &default_settings,
        "The render settings' defaults, by the keys Session.render and Viewport.draw read.");
  m.def("devices", [] {
    py::list out;
    for (const auto& info : rtsdf::vk::Context::list_devices()) out.append(describe(info));
    return out;
  }, "Vulkan devices the loader sees (name, type, api_version, driver).");
  m.def("device_info", [] {
    rtsdf::vk::Context context;
    return describe(context.info());
  }, "The device RTSDF would use (honours RTSDF_DEVICE).");
  py::class_<Viewport>(m, "Viewport", "A viewport's scene and progressive renderer (Session.viewport()).")
      .def("sync", &Viewport::sync, py::arg("scene"),
           "Uploads the scene's meshes and instances (as Session.render takes them); later changes come through "
           "set_transforms and set_mesh.")
      .def("update", &Viewport::update, py::arg("scene"),
           "The scene as it is now (as sync takes it): only what changed is uploaded, in place where the meshes, "
           "instances, materials and images keep their structure (new transforms, a deformed mesh's geometry), "
           "else afresh. Returns whether anything changed.")
      .def("set_transforms", &Viewport::set_transforms, py::arg("matrices"),
           "A 4x4 matrix for every instance, in sync's order (only the top-level BVH is rebuilt).")
      .def("set_mesh", &Viewport::set_mesh, py::arg("mesh"), py::arg("positions"),
           "New vertex positions (N, 3) of mesh `mesh`, same vertex count and triangles.")
      .def("set_mesh_geometry", &Viewport::set_mesh_geometry, py::arg("mesh"), py::arg("geometry"),
           "New geometry of mesh `mesh` (a dict as sync's meshes: positions, indices, optional normals), in any "
           "number of vertices and triangles; the same geometry again changes nothing.")
      .def("restart", &Viewport::restart,
           "The next draw starts a new accumulation of the same view and settings, as after a change.")
      .def("fine_sdf", &Viewport::fine_sdf, py::arg("mesh") = 0,
           "The fine SDF as the last draw left it: {space, origin, voxel_size, distance (z, y, x) as float32}: "
           "mesh `mesh`'s own field in object space (rtsdf), else the whole scene's in world space; None before "
           "the first fine-SDF update.")
      .def("draw", &Viewport::draw, py::arg("view"), py::arg("settings") = py::dict(),
           "Adds one accumulation frame of the view {camera, lights, ambient, width, height} and returns combined "
           "(H,W,4, rows top to bottom), frames, converged, advanced and ms. Any change of scene, view or settings "
           "starts afresh; once settings['samples'] frames are in, it does no work.");
  py::class_<Session>(m, "Session", "A Vulkan device and renderer kept between renders.")
      .def(py::init<>())
      .def_property_readonly("device", &Session::device)
      .def_property_readonly("validation_messages", &Session::validation_messages,
                             "Vulkan validation messages so far on this session's device (RTSDF_VALIDATION=1).")
      .def("viewport", &Session::viewport, "A new viewport (its own scene and accumulation) on this device.")
      .def("forget_fields", &Session::forget_fields,
           "Drops the refined fields kept for later renders and viewports (each mesh's next render builds its own).")
      .def_property_readonly("kept_fields", &Session::kept_fields,
                             "The refined fields kept for later renders: count, mb and capacity_mb.")
      .def("set_field_store", &Session::set_field_store, py::arg("directory"), py::arg("capacity_mb") = 2048.0,
           "Keeps refined fields in `directory` as well (made if missing), at most capacity_mb of files, the least "
           "recently used going first, so that a later process takes them instead of tracing them again. Files "
           "are only read by the build that wrote them. '' keeps fields in memory only (the default).")
      .def_property_readonly("field_store", &Session::field_store,
                             "None, or the field store's directory, capacity_mb, files and mb in it, and what this "
                             "process did with it: loaded, saved, passed_over (unreadable files), failed_saves and "
                             "last_error.")
      .def("render", &Session::render, py::arg("scene"), py::arg("settings") = py::dict(),
           py::arg("progress") = py::none(), py::arg("persistent") = false,
           "Renders a scene given as plain data: meshes [{positions (N,3), indices (M,3), normals (N,3) optional}], instances "
           "[{mesh, matrix 4x4 row-major, color, casts_shadow, visible_camera, holdout}], lights [{type SUN|POINT|SPOT|AREA, position, direction, color, "
           "energy, angle, radius, spot_size, spot_blend}], camera {world_to_view, projection (OpenGL), "
           "orthographic}, width, height, ambient. settings: the RenderSettings fields by name, among them "
           "shadow_method ('rtsdf', 'rtsdf_world', 'rt_only', 'jfa_only', 'csm_evsm', 'csm_jitter' or 'raytraced') and shadow_map_size (the csm methods). "
           "Returns combined (H,W,4), depth, shadow (rows top to bottom) "
           "and ms. progress(done, total, preview) is called after each accumulation frame (preview() reads the "
           "Combined image so far); returning False stops. "
           "persistent=True keeps the scene on the device and the fine SDF between renders where only transforms "
           "or meshes' geometry change (Blender's persistent data); the result's scene_reused tells whether it did.");
  m.def(
      "write_exr",
      [](const std::string& path, const py::dict& result) {
        auto plane = [&](const char* name) {
          return result[name].cast<py::array_t<float, py::array::c_style | py::array::forcecast>>();
        };
        auto combined = plane("combined"), depth = plane("depth"), shadow = plane("shadow");
        if (combined.ndim() != 3 || combined.shape(2) != 4 || depth.ndim() != 2 || shadow.ndim() != 2 ||
            depth.shape(0) != combined.shape(0) || depth.shape(1) != combined.shape(1) ||
            shadow.shape(0) != combined.shape(0) || shadow.shape(1) != combined.shape(1))
          throw rtsdf::Error("write_exr: combined must be (H, W, 4) and depth, shadow (H, W)");
        rtsdf::RenderOutput out;
        out.height = int(combined.shape(0));
        out.width = int(combined.shape(1));
        out.combined.assign(combined.data(), combined.data() + combined.size());
        out.depth.assign(depth.data(), depth.data() + depth.size());
        out.shadow.assign(shadow.data(), shadow.data() + shadow.size());
        rtsdf::write_exr(path, out);
      },
      py::arg("path"), py::arg("result"),
      "Writes a render result (Session.render's combined, depth, shadow) to an OpenEXR file: linear float "
      "channels R, G, B, A, Z and Shadow.");
  m.def("coarse_sdf", &coarse_sdf, py::arg("positions"), py::arg("indices"), py::arg("coarse_resolution") = 64,
        py::arg("beta") = 0.5f,
        "Coarse SDF of one triangle mesh. Returns a dict with 'distance' [z, y, x] in world units, 'origin', "
        "'voxel_size', 'dims', 'beta' (world units), 'device' and 'ms'.");
}
