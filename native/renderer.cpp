#include "renderer.h"

#include <chrono>
#include <cmath>
#include <cstring>
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

float halton(uint32_t index, uint32_t base) {
  float f = 1.0f, r = 0.0f;
  for (uint32_t i = index + 1; i > 0; i /= base) f /= float(base), r += f * float(i % base);
  return r;
}

template <typename T>
std::vector<T> read_plane(const vk::Context& context, const vk::Image& image, int channels) {
  vk::Buffer readback = vk::download_image(context, image, sizeof(float) * channels);
  std::vector<T> values(image.texel_count() * channels);
  std::memcpy(values.data(), readback.mapped(), values.size() * sizeof(T));
  return values;
}

}  // namespace

Renderer::Renderer(const vk::Context& context)
    : context_(context), coarse_(context), fine_(context), gbuffer_(context), shade_(context) {}

RenderOutput Renderer::render(GpuScene& scene, const Camera& camera, const std::vector<Light>& lights,
                              glm::vec3 ambient, int width, int height, const RenderSettings& settings,
                              const Progress& progress) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) + " is out of range (1 to 16384)");
  if (settings.samples < 1 || settings.samples > 4096) throw Error("samples must be 1 to 4096");
  if (settings.sdf_updates < 0 || settings.sdf_updates > 4096) throw Error("sdf_updates must be 0 (every frame) to 4096");
  if (settings.shadow_max_steps < 1 || settings.shadow_max_steps > 4096) throw Error("shadow_max_steps must be 1 to 4096");
  if (!(settings.shadow_epsilon > 0.0f) || !(settings.max_step > 0.0f))
    throw Error("shadow_epsilon and max_step must be positive");
  const Clock::time_point start = Clock::now();
  RenderOutput out;
  out.width = width;
  out.height = height;

  Clock::time_point step = Clock::now();
  // The SDFs hold only what can shadow something, on grids fitted to it.
  scene.set_shadow_casters(find_shadow_casters(scene.scene(), lights));
  const bool has_casters = !scene.shadow_casters().empty();
  GridSpec fine_grid;
  if (has_casters) {
    const GridSpec coarse_grid = fit_grid(scene.bounds(), settings.coarse_resolution);
    coarse_.build(scene, coarse_grid, settings.beta);
    fine_grid = FineSdf::fit(coarse_grid, settings.fine_resolution);
    if (!settings.keep_history) fine_.reset();  // (a new grid resets it anyway)
  } else if (!no_casters_field_) {
    // Nothing casts shadows: a one-texel field the shading never marches.
    no_casters_field_ = std::make_unique<vk::Image>(context_, glm::ivec3(1), VK_FORMAT_R32_SFLOAT,
                                                    VK_IMAGE_USAGE_STORAGE_BIT);
    context_.submit_and_wait([&](VkCommandBuffer cmd) {
      vk::image_barrier(cmd, no_casters_field_->handle(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, 0,
                        VK_ACCESS_SHADER_READ_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
    });
  }
  const vk::Image& field = has_casters ? fine_.distance() : *no_casters_field_;
  out.timings.coarse_ms = ms_since(step);

  const std::vector<gpu::GpuLight> gpu_lights = to_gpu(lights);
  vk::Buffer light_buffer = vk::upload_buffer(context_, gpu_lights.data(), gpu_lights.size() * sizeof(gpu::GpuLight),
                                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  vk::Buffer frame(context_, sizeof(gpu::FrameData), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::Buffer::Access::HostVisible);
  gbuffer_.resize(width, height);
  const VkImageUsageFlags usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  vk::Image accum_color = vk::Image::plane(context_, width, height, VK_FORMAT_R32G32B32A32_SFLOAT, usage);
  vk::Image accum_passes = vk::Image::plane(context_, width, height, VK_FORMAT_R32G32_SFLOAT, usage);
  context_.submit_and_wait([&](VkCommandBuffer cmd) {
    for (const vk::Image* image : {&accum_color, &accum_passes})
      vk::image_barrier(cmd, image->handle(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, 0,
                        VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  });

  const glm::mat4 view_to_world = glm::inverse(camera.world_to_view);
  gpu::FrameData data{};
  data.camera_position = glm::vec4(glm::vec3(view_to_world[3]), camera.orthographic ? 1.0f : 0.0f);
  data.camera_forward = glm::vec4(-glm::normalize(glm::vec3(view_to_world[2])), 0.0f);
  data.ambient = glm::vec4(ambient, 0.0f);

  gpu::ShadePush push{};
  push.fine_grid = glm::vec4(fine_grid.origin, fine_grid.voxel_size);
  push.fine_dims = glm::ivec4(fine_grid.dims, has_casters ? settings.shadow_max_steps : 0);
  push.march = glm::vec4(settings.shadow_epsilon * fine_grid.voxel_size, settings.max_step * fine_grid.voxel_size,
                         1.0f * fine_grid.voxel_size, 0.0f);
  for (int sample = 0; sample < settings.samples; ++sample) {
    step = Clock::now();
    if (has_casters && (settings.sdf_updates == 0 || sample < settings.sdf_updates))
      fine_.update(scene, coarse_, fine_grid, settings.fine);
    out.timings.fine_ms += ms_since(step);

    step = Clock::now();
    // Sub-pixel jitter (Halton 2,3) for anti-aliasing, averaged over samples.
    const glm::vec2 jitter(halton(uint32_t(sample), 2) - 0.5f, halton(uint32_t(sample), 3) - 0.5f);
    const glm::mat4 shift = glm::translate(glm::mat4(1.0f), glm::vec3(2.0f * jitter.x / float(width),
                                                                     2.0f * jitter.y / float(height), 0.0f));
    data.world_to_clip = shift * kGlToVulkan * camera.projection * camera.world_to_view;
    std::memcpy(frame.mapped(), &data, sizeof data);
    push.image = glm::ivec4(width, height, int(gpu_lights.size()), sample);
    push.march.w = 1.0f / float(sample + 1);
    context_.submit_and_wait([&](VkCommandBuffer cmd) {
      gbuffer_.record(cmd, scene, frame);
      shade_.record(cmd, gbuffer_, field, light_buffer, frame, accum_color, accum_passes, push);
    });
    out.timings.shade_ms += ms_since(step);
    out.samples_done = sample + 1;
    if (progress && !progress(sample + 1, settings.samples)) break;
  }

  out.combined = read_plane<float>(context_, accum_color, 4);
  std::vector<float> passes = read_plane<float>(context_, accum_passes, 2);
  out.depth.resize(size_t(width) * height);
  out.shadow.resize(size_t(width) * height);
  for (size_t i = 0; i < out.depth.size(); ++i) out.depth[i] = passes[2 * i], out.shadow[i] = passes[2 * i + 1];
  out.timings.total_ms = ms_since(start);
  return out;
}

}  // namespace rtsdf
