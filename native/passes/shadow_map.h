#pragma once
// The csm_evsm baseline's visibility (the paper's comparison): shadow maps
// filtered as exponential variance shadow maps (EVSM, Lauritzen). Every light
// gets views fitted to the camera and the scene:
// - sun: kCascades orthographic cascades over slices of the camera's depth
//   range (practical split scheme), each fitted to its slice's bounding
//   sphere and snapped to whole texels so edges do not shimmer as the camera moves;
// - spot: one perspective view over its cone;
// - point and area: a cube of six perspective faces.
// Each view is a square tile of one atlas. The raster pass writes the EVSM
// moments of the nearest caster; a separable box blur, as wide as the light's
// angular size makes a penumbra at a reference occluder distance, filters them;
// shade.comp takes the Chebyshev bound of both warps.
#include <memory>
#include <vector>

#include "gpu_scene.h"
#include "lights.h"
#include "shaders/shared.h"
#include "vk/pipeline.h"
#include "vk/resources.h"

namespace rtsdf {

class ShadowMapPass {
 public:
  static constexpr int kCascades = 4;
  static constexpr float kSplitLambda = 0.7f;  // practical split scheme: 0 uniform, 1 logarithmic
  // EVSM warps: 40 is about the most e^(2 c x) (x in [-1, 1]) leaves room for in 32-bit floats.
  static constexpr float kPositiveExponent = 40.0f;
  static constexpr float kNegativeExponent = 5.0f;
  // Chebyshev bounds below this share read as full shadow (fights EVSM's light bleeding).
  static constexpr float kLightBleedingReduction = 0.1f;
  // Box radius cap, in texels: the blur's cost grows with it.
  static constexpr float kMaxBlurRadius = 24.0f;
  // Texels of all tiles together; more tiles get smaller ones (16 M texels: 256 MiB of moments).
  static constexpr long kMaxAtlasTexels = 16l << 20;

  explicit ShadowMapPass(const vk::Context& context);

  // Fits every light's views to the camera (world_to_view, an OpenGL-style
  // `projection`) and to the scene's shadow casters, with `size` texels per
  // tile side, and (re)allocates the atlas. Throws rtsdf::Error for a bad size.
  void setup(const GpuScene& scene, const std::vector<Light>& lights, const glm::mat4& world_to_view,
             const glm::mat4& projection, int size);
  // Renders the shadow casters into every tile and blurs the moments.
  void record(VkCommandBuffer cmd, const GpuScene& scene) const;

  // What shade.comp reads: the moments atlas, the tiles and each light's range of them.
  const vk::Image& moments() const { return moments_; }
  const vk::Buffer& tiles() const { return tiles_; }
  const vk::Buffer& light_tiles() const { return light_tiles_; }
  int tile_size() const { return tile_size_; }

  // The views of the last setup (for tests): tiles, their blur radii in
  // texels, and the cascade split depths of each sun (kCascades + 1 each).
  const std::vector<gpu::ShadowTile>& tile_data() const { return tile_data_; }
  const std::vector<float>& blur_radii() const { return blur_radii_; }
  const std::vector<float>& cascade_splits() const { return splits_; }

 private:
  const vk::Context& context_;
  vk::Pipeline raster_;
  vk::Pipeline blur_;
  int tile_size_ = 0;
  glm::ivec2 atlas_tiles_{0};  // columns, rows
  std::vector<gpu::ShadowTile> tile_data_;
  std::vector<float> blur_radii_;
  std::vector<float> splits_;
  vk::Image moments_;
  vk::Image blur_scratch_;  // one tile: the horizontal pass's output
  vk::Image depth_;
  std::unique_ptr<vk::Framebuffer> framebuffer_;
  vk::Buffer tiles_;
  vk::Buffer light_tiles_;
};

}  // namespace rtsdf
