#pragma once
// GPU timestamps around the passes of one command buffer.
#include <volk.h>

#include <string>
#include <vector>

namespace rtsdf::vk {

class Context;

class GpuTimer {
 public:
  GpuTimer(const Context& context, uint32_t capacity);
  ~GpuTimer();
  GpuTimer(const GpuTimer&) = delete;
  GpuTimer& operator=(const GpuTimer&) = delete;

  // Call once at the start of a command buffer, then mark() after each pass.
  void begin(VkCommandBuffer cmd);
  void mark(VkCommandBuffer cmd, std::string label);
  // After the submission completed: milliseconds of each marked pass, in order.
  struct Span {
    std::string label;
    double ms;
  };
  std::vector<Span> read() const;

 private:
  VkDevice device_;
  double period_ns_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint32_t capacity_;
  std::vector<std::string> labels_;
};

}  // namespace rtsdf::vk
