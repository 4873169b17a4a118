#include "vk/timer.h"

#include "vk/context.h"

namespace rtsdf::vk {

GpuTimer::GpuTimer(const Context& context, uint32_t capacity)
    : device_(context.device()), period_ns_(context.timestamp_period_ns()), capacity_(capacity) {
  if (period_ns_ <= 0.0) throw Error("Vulkan device " + context.info().name + " has no timestamp queries");
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = capacity;
  VK_CHECK(vkCreateQueryPool(device_, &info, nullptr, &pool_));
}

GpuTimer::~GpuTimer() { vkDestroyQueryPool(device_, pool_, nullptr); }

void GpuTimer::begin(VkCommandBuffer cmd) {
  labels_.clear();
  vkCmdResetQueryPool(cmd, pool_, 0, capacity_);
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, pool_, 0);
}

void GpuTimer::mark(VkCommandBuffer cmd, std::string label) {
  if (labels_.size() + 1 >= capacity_) throw Error("GpuTimer capacity exceeded");
  labels_.push_back(std::move(label));
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_, uint32_t(labels_.size()));
}

std::vector<GpuTimer::Span> GpuTimer::read() const {
  std::vector<uint64_t> ticks(labels_.size() + 1);
  VK_CHECK(vkGetQueryPoolResults(device_, pool_, 0, uint32_t(ticks.size()), ticks.size() * sizeof(uint64_t),
                                 ticks.data(), sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  std::vector<Span> spans;
  for (size_t i = 0; i < labels_.size(); ++i)
    spans.push_back({labels_[i], double(ticks[i + 1] - ticks[i]) * period_ns_ * 1e-6});
  return spans;
}

}  // namespace rtsdf::vk
