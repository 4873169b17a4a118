#pragma once
// The shadow-map baselines' visibility: shadow maps of exponential variance
// moments (EVSM, Lauritzen) for csm_evsm (the paper's comparison) and
// csm_jitter (EEVEE's soft shadows). Every light gets views fitted to the
// camera and the scene:
// - sun: kCascades orthographic cascades over slices of the camera's depth
//   range (practical split scheme), each fitted to its slice's bounding
//   sphere and snapped to whole texels so edges do not shimmer as the camera moves;
// - spot: one perspective view over its cone;
// - point and area: a cube of six perspective faces.
// Each view is a square tile of one atlas. The raster pass writes the EVSM
// moments of the nearest caster. The shading filters them per pixel
// (shaders/shadow_map_lookup.glsl.h): csm_evsm over a disk as wide as the
// penumbra a blocker search finds (PCSS), csm_jitter over a texel of a map
// whose origin moves over the light every frame. Then it takes the Chebyshev
// bound of both warps.
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
  // EVSM warps: 42 is about the most e^(2 c x) (x in [-1, 1]) leaves room for
  // in 32-bit floats; both warps take it.
  static constexpr float kPositiveExponent = 42.0f;
  static constexpr float kNegativeExponent = 10.0f;
  // Chebyshev bounds below this share read as full shadow (fights EVSM's light bleeding).
  static constexpr float kLightBleedingReduction = 0.1f;
  // The widest filter, in texels (its taps spread thinner as it widens).
  static constexpr float kMaxFilterRadius = 32.0f;
  // Texels of all tiles together; more tiles get smaller ones (16 M texels: 256 MiB of moments).
  static constexpr long kMaxAtlasTexels = 16l << 20;

  explicit ShadowMapPass(const vk::Context& context);

  // Fits every light's views to the camera (world_to_view, an OpenGL-style
  // `projection`) and to the scene's shadow casters, with `size` texels per
  // tile side, and (re)allocates the atlas. `filter_radius` (texels): the
  // lookup's fixed filter, 0 for a penumbra-wide one. Throws rtsdf::Error for a bad size.
  void setup(const GpuScene& scene, const std::vector<Light>& lights, const glm::mat4& world_to_view,
             const glm::mat4& projection, int size, float filter_radius);
  // Renders the shadow casters into every tile.
  void record(VkCommandBuffer cmd, const GpuScene& scene) const;

  // What shade.comp reads: the moments atlas, the tiles and each light's range of them.
  const vk::Image& moments() const { return moments_; }
  const vk::Buffer& tiles() const { return tiles_; }
  const vk::Buffer& light_tiles() const { return light_tiles_; }
  int tile_size() const { return tile_size_; }

  // The views of the last setup (for tests).
  const std::vector<gpu::ShadowTile>& tile_data() const { return tile_data_; }

 private:
  const vk::Context& context_;
  vk::Pipeline raster_;
  int tile_size_ = 0;
  glm::ivec2 atlas_tiles_{0};  // columns, rows
  std::vector<gpu::ShadowTile> tile_data_;
  vk::Image moments_;
  vk::Image depth_;
  std::unique_ptr<vk::Framebuffer> framebuffer_;
  vk::Buffer tiles_;
  vk::Buffer light_tiles_;
};

}  // namespace rtsdf
