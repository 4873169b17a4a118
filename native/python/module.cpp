// rtsdf_native: the native core seen from Python (and Blender's Python).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "coarse_sdf.h"
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

}  // namespace

PYBIND11_MODULE(rtsdf_native, m) {
  m.doc() = "RTSDF native core: real-time signed distance fields on Vulkan";
  py::register_exception<rtsdf::Error>(m, "Error", PyExc_RuntimeError);
  m.attr("__version__") = rtsdf::kVersion;
  m.def("devices", [] {
    py::list out;
    for (const auto& info : rtsdf::vk::Context::list_devices()) out.append(describe(info));
    return out;
  }, "Vulkan devices the loader sees (name, type, api_version, driver).");
  m.def("device_info", [] {
    rtsdf::vk::Context context;
    return describe(context.info());
  }, "The device RTSDF would use (honours RTSDF_DEVICE).");
  m.def("coarse_sdf", &coarse_sdf, py::arg("positions"), py::arg("indices"), py::arg("coarse_resolution") = 64,
        py::arg("beta") = 0.5f,
        "Coarse SDF of one triangle mesh. Returns a dict with 'distance' [z, y, x] in world units, 'origin', "
        "'voxel_size', 'dims', 'beta' (world units), 'device' and 'ms'.");
}
