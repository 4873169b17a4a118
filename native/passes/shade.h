#pragma once
// Pass 3b: shading with soft shadows (see shaders/shade.comp), averaged into
// the Combined and Depth/Shadow accumulation images. Visibility marches the
// distance fields in `fields` (fine SDFs, or the coarse one for jfa_only) or
// looks up the EVSM shadow maps of csm_evsm. Some of it is marched at a
// quarter of the pixels first (shaders/quad_visibility.comp): the world
// light's always, the lights' in a shared-visibility frame.
#include <array>
#include <map>
#include <memory>

#include "gpu_scene.h"
#include "grid.h"
#include "march_fields.h"
#include "passes/gbuffer.h"
#include "passes/shadow_map.h"
#include "passes/temporal.h"
#include "shaders/shared.h"
#include "vk/pipeline.h"
#include "vk/resources.h"
#include "vk/timer.h"

namespace rtsdf {

// What the shading reads: the G-buffer, the fields the march reads, the
// shadow maps (only with kVisibilityShadowMaps), the shadow casters' BVHs
// (only with kVisibilityRayTraced or kVisibilityHybrid; null: placeholders
// are bound and nothing blocks), the lights and the frame's data.
struct ShadeInputs {
  const GBufferPass& gbuffer;
  const MarchFields& fields;
  const ShadowMapPass* shadow_maps;
  const GpuScene::RayStructures* rays;
  const vk::Buffer& lights;
  const vk::Buffer& frame;
  // With push.listed_tiles: the tiles holding pixels to shade, listed by the
  // keep pass or the converged test (TemporalPass::kept_tiles); the passes
  // run there alone.
  const KeptTiles* kept_tiles;
};

// The running means it adds this frame's sample to.
struct ShadeTargets {
  const vk::Image& accum_color;   // rgb = Combined, a = coverage
  const vk::Image& accum_passes;  // Depth, Shadow, samples, farthest depth
  const vk::Image& accum_moments;  // the samples' second moments (shaders/sample_moments.glsl.h)
};

class ShadePass {
 public:
  static constexpr int kMaxSharedLights = 16;
  explicit ShadePass(const vk::Context& context);
  // Sizes the quad pass's outputs and the fill list for an image and a light
  // count (outside a command buffer: a new image is set up by a submission).
  void resize(glm::ivec2 size, int lights);
  // `march_sky`: the world
  // light is marched (it has some colour and the method is an SDF's).
  // `share_lights` (SDF methods only): the lights' visibility too is marched
  // at one pixel of each 2x2 quad and taken from there by the pixels on the
  // same surface; the others (silhouettes, thin parts) march their own in a
  // third pass over just those pixels. About half the cost of marching
  // every pixel, with penumbrae resolved at a quarter of the pixels: for the
  // viewport's frame after a change, whose later accumulation frames march
  // every pixel.
  // Lights are shared up to kMaxSharedLights (the quad pass keeps a value
  // per light and quad); with more, every pixel marches them.
  // `timer` (optional) gets a "quad" mark after the quad pass.
  void record(VkCommandBuffer cmd, const ShadeInputs& in, const ShadeTargets& out, bool march_sky, bool share_lights,
              const gpu::ShadePush& push, vk::GpuTimer* timer = nullptr);

 private:
  // The passes, specialized so that each holds only its visibility method's
  // (kVisibility*), its part's (kShade*) and its field view's (kDebug*)
  // code; each made on its first use.
  enum class Shader { Quad, Shade };
  const vk::Pipeline& pipeline(Shader shader, uint32_t mode, uint32_t stage, uint32_t field_view);

  const vk::Context& context_;
  std::map<std::array<uint32_t, 4>, std::unique_ptr<vk::Pipeline>> pipelines_;
  vk::Image no_shadow_atlas_;   // 1 texel
  vk::Buffer no_shadow_tiles_;  // one tile, and one light's empty range (also stands in for the BVHs)
  vk::Buffer no_rays_;          // a BVH node with no instance: nothing to hit
  glm::ivec2 size_{0};
  vk::Image quad_samples_;      // per 2x2 quad: its sample's normal and world light
  vk::Buffer quad_lights_;      // per light and quad: the light's visibility at the quad's sample
  vk::Buffer fill_list_;        // the fill pass's indirect dispatch, then the pixels it shades
  vk::Buffer sky_list_;         // the sky pass's, then the quads whose world light it marches
};

}  // namespace rtsdf
