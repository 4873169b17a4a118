#include "vk/pipeline.h"

#include "vk/context.h"
#include "vk/resources.h"

namespace rtsdf::vk {

namespace {

class ShaderModule {
 public:
  ShaderModule(VkDevice device, Spirv code) : device_(device) {
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = code.bytes;
    info.pCode = code.words;
    VK_CHECK(vkCreateShaderModule(device_, &info, nullptr, &module_));
  }
  ~ShaderModule() { vkDestroyShaderModule(device_, module_, nullptr); }
  ShaderModule(const ShaderModule&) = delete;
  ShaderModule& operator=(const ShaderModule&) = delete;
  VkShaderModule handle() const { return module_; }

 private:
  VkDevice device_;
  VkShaderModule module_ = VK_NULL_HANDLE;
};

VkPipelineShaderStageCreateInfo stage_info(VkShaderStageFlagBits stage, const ShaderModule& module) {
  VkPipelineShaderStageCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  info.stage = stage;
  info.module = module.handle();
  info.pName = "main";
  return info;
}

// The values of a shader's 32-bit constants (constant_id i: values[i]), as
// stages take them; `entries` holds what the info points to.
VkSpecializationInfo specialization_info(const std::vector<uint32_t>& values,
                                         std::vector<VkSpecializationMapEntry>& entries) {
  entries.clear();
  for (uint32_t i = 0; i < values.size(); ++i) entries.push_back({i, uint32_t(i * sizeof(uint32_t)), sizeof(uint32_t)});
  return {uint32_t(entries.size()), entries.data(), values.size() * sizeof(uint32_t), values.data()};
}

// A pipeline's Vulkan objects, destroyed with the last Pipeline or context that holds them.
struct PipelineObjects {
  VkDevice device = VK_NULL_HANDLE;
  VkShaderStageFlags stages = 0;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkRenderPass render_pass = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  explicit PipelineObjects(VkDevice d) : device(d) {}
  PipelineObjects(const PipelineObjects&) = delete;
  PipelineObjects& operator=(const PipelineObjects&) = delete;
  ~PipelineObjects() {
    if (pipeline) vkDestroyPipeline(device, pipeline, nullptr);
    if (render_pass) vkDestroyRenderPass(device, render_pass, nullptr);
    if (layout) vkDestroyPipelineLayout(device, layout, nullptr);
    if (set_layout) vkDestroyDescriptorSetLayout(device, set_layout, nullptr);
  }
};

void create_layout(PipelineObjects& objects, const std::vector<VkDescriptorType>& bindings, uint32_t push_bytes,
                   VkShaderStageFlags stages) {
  objects.stages = stages;
  std::vector<VkDescriptorSetLayoutBinding> layout_bindings;
  for (uint32_t i = 0; i < bindings.size(); ++i) layout_bindings.push_back({i, bindings[i], 1, stages, nullptr});
  VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  set_info.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
  set_info.bindingCount = uint32_t(layout_bindings.size());
  set_info.pBindings = layout_bindings.data();
  VK_CHECK(vkCreateDescriptorSetLayout(objects.device, &set_info, nullptr, &objects.set_layout));
  VkPushConstantRange range{stages, 0, push_bytes};
  VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layout_info.setLayoutCount = 1;
  layout_info.pSetLayouts = &objects.set_layout;
  layout_info.pushConstantRangeCount = push_bytes > 0 ? 1 : 0;
  layout_info.pPushConstantRanges = &range;
  VK_CHECK(vkCreatePipelineLayout(objects.device, &layout_info, nullptr, &objects.layout));
}

// What tells pipelines apart: every creation parameter, the shaders by their
// words' address (each a constant array of the binary).
template <typename T>
void append(std::string& key, const T& value) {
  key.append(reinterpret_cast<const char*>(&value), sizeof value);
}

std::string pipeline_key(std::initializer_list<Spirv> shaders, const std::vector<VkDescriptorType>& bindings,
                         uint32_t push_bytes, const std::vector<uint32_t>& words) {
  std::string key;
  for (const Spirv& shader : shaders) append(key, shader.words), append(key, shader.bytes);
  append(key, bindings.size());
  for (VkDescriptorType type : bindings) append(key, type);
  append(key, push_bytes);
  for (uint32_t word : words) append(key, word);
  return key;
}

}  // namespace

Resource Resource::storage_image(const Image& image) {
  Resource r{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
  r.image = {VK_NULL_HANDLE, image.view(), VK_IMAGE_LAYOUT_GENERAL};
  return r;
}

Resource Resource::storage_buffer(const Buffer& buffer) {
  Resource r{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
  r.buffer = {buffer.handle(), 0, VK_WHOLE_SIZE};
  return r;
}

Resource Resource::uniform_buffer(const Buffer& buffer) {
  Resource r{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER};
  r.buffer = {buffer.handle(), 0, VK_WHOLE_SIZE};
  return r;
}

Pipeline::Pipeline(const Context& context, Spirv compute, std::vector<VkDescriptorType> bindings,
                   uint32_t push_bytes, const std::vector<uint32_t>& specialization)
    : bind_point_(VK_PIPELINE_BIND_POINT_COMPUTE) {
  adopt(context.shared(pipeline_key({compute}, bindings, push_bytes, specialization), [&] {
    auto objects = std::make_shared<PipelineObjects>(context.device());
    create_layout(*objects, bindings, push_bytes, VK_SHADER_STAGE_COMPUTE_BIT);
    ShaderModule module(objects->device, compute);
    std::vector<VkSpecializationMapEntry> entries;
    const VkSpecializationInfo constants = specialization_info(specialization, entries);
    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.stage = stage_info(VK_SHADER_STAGE_COMPUTE_BIT, module);
    if (!specialization.empty()) info.stage.pSpecializationInfo = &constants;
    info.layout = objects->layout;
    VK_CHECK(vkCreateComputePipelines(objects->device, VK_NULL_HANDLE, 1, &info, nullptr, &objects->pipeline));
    return std::shared_ptr<const void>(objects);
  }));
}

Pipeline::Pipeline(const Context& context, Spirv vertex, Spirv fragment, std::vector<VkDescriptorType> bindings,
                   uint32_t push_bytes, const RenderTargets& targets, const std::vector<uint32_t>& specialization)
    : bind_point_(VK_PIPELINE_BIND_POINT_GRAPHICS) {
  std::vector<uint32_t> key_words{uint32_t(targets.colors.size())};
  key_words.insert(key_words.end(), targets.colors.begin(), targets.colors.end());
  key_words.push_back(uint32_t(targets.depth));
  key_words.insert(key_words.end(), specialization.begin(), specialization.end());
  adopt(context.shared(pipeline_key({vertex, fragment}, bindings, push_bytes, key_words), [&] {
    auto objects = std::make_shared<PipelineObjects>(context.device());
    const VkDevice device = objects->device;
    create_layout(*objects, bindings, push_bytes, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT);

    std::vector<VkAttachmentDescription> attachments;
    std::vector<VkAttachmentReference> color_refs;
    for (VkFormat format : targets.colors) {
      color_refs.push_back({uint32_t(attachments.size()), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL});
      attachments.push_back({0, format, VK_SAMPLE_COUNT_1_BIT, VK_ATTACHMENT_LOAD_OP_CLEAR,
                             VK_ATTACHMENT_STORE_OP_STORE, VK_ATTACHMENT_LOAD_OP_DONT_CARE,
                             VK_ATTACHMENT_STORE_OP_DONT_CARE, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL});
    }
    const bool has_depth = targets.depth != VK_FORMAT_UNDEFINED;
    VkAttachmentReference depth_ref{uint32_t(attachments.size()), VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    if (has_depth)
      attachments.push_back({0, targets.depth, VK_SAMPLE_COUNT_1_BIT, VK_ATTACHMENT_LOAD_OP_CLEAR,
                             VK_ATTACHMENT_STORE_OP_DONT_CARE, VK_ATTACHMENT_LOAD_OP_DONT_CARE,
                             VK_ATTACHMENT_STORE_OP_DONT_CARE, VK_IMAGE_LAYOUT_UNDEFINED,
                             VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL});
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = uint32_t(color_refs.size());
    subpass.pColorAttachments = color_refs.data();
    subpass.pDepthStencilAttachment = has_depth ? &depth_ref : nullptr;
    VkSubpassDependency after{};  // attachment and storage writes visible to later compute and transfer
    after.srcSubpass = 0;
    after.dstSubpass = VK_SUBPASS_EXTERNAL;
    after.srcStageMask = VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    after.dstStageMask = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    after.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    after.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT;
    VkSubpassDependency before{};  // earlier compute reads of the targets finish before they are cleared
    before.srcSubpass = VK_SUBPASS_EXTERNAL;
    before.dstSubpass = 0;
    before.srcStageMask = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    before.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                          VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT;
    before.srcAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
    before.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                           VK_ACCESS_SHADER_WRITE_BIT;
    VkSubpassDependency dependencies[] = {before, after};
    VkRenderPassCreateInfo pass_info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    pass_info.attachmentCount = uint32_t(attachments.size());
    pass_info.pAttachments = attachments.data();
    pass_info.subpassCount = 1;
    pass_info.pSubpasses = &subpass;
    pass_info.dependencyCount = 2;
    pass_info.pDependencies = dependencies;
    VK_CHECK(vkCreateRenderPass(device, &pass_info, nullptr, &objects->render_pass));

    ShaderModule vs(device, vertex), fs(device, fragment);
    VkPipelineShaderStageCreateInfo stages[] = {stage_info(VK_SHADER_STAGE_VERTEX_BIT, vs),
                                                stage_info(VK_SHADER_STAGE_FRAGMENT_BIT, fs)};
    std::vector<VkSpecializationMapEntry> entries;
    const VkSpecializationInfo constants = specialization_info(specialization, entries);
    if (!specialization.empty())
      for (VkPipelineShaderStageCreateInfo& stage : stages) stage.pSpecializationInfo = &constants;
    VkPipelineVertexInputStateCreateInfo vertex_input{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;
    raster.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    depth.depthTestEnable = has_depth;
    depth.depthWriteEnable = has_depth;
    depth.depthCompareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
    std::vector<VkPipelineColorBlendAttachmentState> blends(targets.colors.size());
    for (auto& b : blends)
      b.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT |
                         VK_COLOR_COMPONENT_A_BIT;
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = uint32_t(blends.size());
    blend.pAttachments = blends.data();
    VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dynamic.dynamicStateCount = 2;
    dynamic.pDynamicStates = dynamic_states;

    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.stageCount = 2;
    info.pStages = stages;
    info.pVertexInputState = &vertex_input;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = objects->layout;
    info.renderPass = objects->render_pass;
    VK_CHECK(vkCreateGraphicsPipelines(device, VK_NULL_HANDLE, 1, &info, nullptr, &objects->pipeline));
    return std::shared_ptr<const void>(objects);
  }));
}

void Pipeline::adopt(std::shared_ptr<const void> objects) {
  const auto& made = *static_cast<const PipelineObjects*>(objects.get());
  stages_ = made.stages;
  layout_ = made.layout;
  render_pass_ = made.render_pass;
  pipeline_ = made.pipeline;
  objects_ = std::move(objects);
}

void Pipeline::bind(VkCommandBuffer cmd) const { vkCmdBindPipeline(cmd, bind_point_, pipeline_); }

void Pipeline::push_descriptors(VkCommandBuffer cmd, const std::vector<Resource>& resources) const {
  std::vector<VkWriteDescriptorSet> writes;
  uint32_t binding = 0;
  for (const Resource& r : resources) {
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstBinding = binding++;
    write.descriptorCount = 1;
    write.descriptorType = r.type;
    if (r.type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER || r.type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER)
      write.pBufferInfo = &r.buffer;
    else
      write.pImageInfo = &r.image;
    writes.push_back(write);
  }
  vkCmdPushDescriptorSetKHR(cmd, bind_point_, layout_, 0, uint32_t(writes.size()), writes.data());
}

void Pipeline::push_constant_bytes(VkCommandBuffer cmd, const void* data, uint32_t bytes) const {
  vkCmdPushConstants(cmd, layout_, stages_, 0, bytes, data);
}

void clear_indirect_dispatch(VkCommandBuffer cmd, const Buffer& buffer, VkDeviceSize offset) {
  const uint32_t no_groups[4] = {0u, 1u, 1u, 0u};
  vkCmdUpdateBuffer(cmd, buffer.handle(), offset, sizeof no_groups, no_groups);
}

void dispatch_grid(VkCommandBuffer cmd, glm::ivec3 dims, glm::ivec3 group) {
  vkCmdDispatch(cmd, group_count(dims.x, group.x), group_count(dims.y, group.y), group_count(dims.z, group.z));
}

Framebuffer::Framebuffer(const Context& context, VkRenderPass pass, uint32_t width, uint32_t height,
                         const std::vector<VkImageView>& views)
    : device_(context.device()) {
  VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  info.renderPass = pass;
  info.attachmentCount = uint32_t(views.size());
  info.pAttachments = views.data();
  info.width = width;
  info.height = height;
  info.layers = 1;
  VK_CHECK(vkCreateFramebuffer(device_, &info, nullptr, &framebuffer_));
}

Framebuffer::~Framebuffer() { vkDestroyFramebuffer(device_, framebuffer_, nullptr); }

}  // namespace rtsdf::vk
