#pragma once
// Compute and graphics pipelines whose resources are bound with push
// descriptors (binding i = i-th resource passed to push_descriptors).
#include <volk.h>

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <initializer_list>
#include <memory>
#include <vector>

namespace rtsdf::vk {

class Context;
class Buffer;
class Image;

struct Spirv {
  const uint32_t* words;
  size_t bytes;
};
#define RTSDF_SPIRV(symbol) ::rtsdf::vk::Spirv{symbol, sizeof(symbol)}

struct Resource {
  VkDescriptorType type;
  VkDescriptorImageInfo image{};
  VkDescriptorBufferInfo buffer{};
  static Resource storage_image(const Image& image);
  static Resource storage_buffer(const Buffer& buffer);
  static Resource uniform_buffer(const Buffer& buffer);
};

// Render targets of a graphics pipeline: colour formats (cleared to zero,
// left in GENERAL layout for compute passes to read) and an optional depth
// format (cleared to 1, less-or-equal test). None: output only by storage writes.
struct RenderTargets {
  std::vector<VkFormat> colors;
  VkFormat depth = VK_FORMAT_UNDEFINED;
};

// Its Vulkan objects are made once per context and creation parameters and
// shared by every Pipeline made alike (see Context::shared): renderers made
// later in a session (a new viewport, the next F12 render) compile nothing.
class Pipeline {
 public:
  // A compute pipeline; `specialization[i]` is the value of the shader's
  // 32-bit constant_id i (the compiler then drops the code it rules out).
  Pipeline(const Context& context, Spirv compute, std::vector<VkDescriptorType> bindings, uint32_t push_bytes,
           const std::vector<uint32_t>& specialization = {});
  // A graphics pipeline drawing triangle lists (no vertex buffers: shaders
  // pull vertices from storage buffers, no culling) into `targets`. Viewport
  // and scissor are dynamic. `specialization` as above, for both stages.
  // Pipelines of the same targets can draw in one another's render passes.
  Pipeline(const Context& context, Spirv vertex, Spirv fragment, std::vector<VkDescriptorType> bindings,
           uint32_t push_bytes, const RenderTargets& targets = {}, const std::vector<uint32_t>& specialization = {});
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  void bind(VkCommandBuffer cmd) const;
  void push_descriptors(VkCommandBuffer cmd, const std::vector<Resource>& resources) const;
  template <typename T>
  void push_constants(VkCommandBuffer cmd, const T& value) const {
    push_constant_bytes(cmd, &value, sizeof(T));
  }
  VkRenderPass render_pass() const { return render_pass_; }

 private:
  void push_constant_bytes(VkCommandBuffer cmd, const void* data, uint32_t bytes) const;
  // Takes the handles of the shared objects (PipelineObjects in pipeline.cpp).
  void adopt(std::shared_ptr<const void> objects);

  std::shared_ptr<const void> objects_;  // owns the handles below
  VkPipelineBindPoint bind_point_;
  VkShaderStageFlags stages_ = 0;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkRenderPass render_pass_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

// A framebuffer for Pipeline's graphics form: the views of its targets, in
// order (colours, then depth), or none.
class Framebuffer {
 public:
  Framebuffer(const Context& context, VkRenderPass pass, uint32_t width, uint32_t height,
              const std::vector<VkImageView>& views = {});
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;
  VkFramebuffer handle() const { return framebuffer_; }

 private:
  VkDevice device_;
  VkFramebuffer framebuffer_ = VK_NULL_HANDLE;
};

// Work groups needed to cover `count` items with groups of `group`.
inline uint32_t group_count(int count, int group) { return uint32_t((count + group - 1) / group); }

// Writes an indirect dispatch of no work groups (x = 0, y = z = 1, then a
// zero word: the lists' count) at `offset` bytes of `buffer`, for a pass that
// lists its work to fill in (a transfer: a barrier must follow).
void clear_indirect_dispatch(VkCommandBuffer cmd, const Buffer& buffer, VkDeviceSize offset = 0);

// Dispatches one invocation per voxel of a dims.x * dims.y * dims.z grid, in
// work groups of the shape the shader declares.
void dispatch_grid(VkCommandBuffer cmd, glm::ivec3 dims, glm::ivec3 group);

}  // namespace rtsdf::vk
