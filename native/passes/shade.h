#pragma once
// Pass 3b: shading with soft shadows (see shaders/shade.comp), averaged into
// the Combined and Depth/Shadow accumulation images. Visibility marches the
// distance fields in `fields` (fine SDFs, or the coarse one for jfa_only) or
// looks up the EVSM shadow maps of csm_evsm.
#include <array>
#include <memory>

#include "grid.h"
#include "march_fields.h"
#include "passes/gbuffer.h"
#include "passes/shadow_map.h"
#include "shaders/shared.h"
#include "vk/pipeline.h"
#include "vk/resources.h"

namespace rtsdf {

class ShadePass {
 public:
  explicit ShadePass(const vk::Context& context);
  // `shadow_maps`: only with push.visibility.x == kVisibilityShadowMaps
  // (null: placeholders are bound in their place). `sky_samples`: one texel
  // per 2x2 quad of the image (see shaders/shade_inputs.glsl.h), marched
  // first when `march_sky` (the world light is marched: it has some colour
  // and the method is an SDF's).
  // The pipelines are made for push.visibility.x's method on its first use.
  void record(VkCommandBuffer cmd, const GBufferPass& gbuffer, const MarchFields& fields,
              const ShadowMapPass* shadow_maps, const vk::Buffer& lights, const vk::Buffer& frame,
              const vk::Image& accum_color, const vk::Image& accum_passes, const vk::Image& sky_samples,
              bool march_sky, const gpu::ShadePush& push);

 private:
  // Per visibility method (kVisibility*): its sky and shading passes,
  // specialized so that each holds only that method's code.
  struct Passes {
    std::unique_ptr<vk::Pipeline> sky, shade;
  };
  const vk::Context& context_;
  std::array<Passes, 3> passes_;
  vk::Image no_shadow_atlas_;   // 1 texel
  vk::Buffer no_shadow_tiles_;  // one tile, and one light's empty range
};

}  // namespace rtsdf
