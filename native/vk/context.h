#pragma once
// One Vulkan instance + device + compute/graphics queue, created headless.
#include <volk.h>

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "error.h"

namespace rtsdf::vk {

const char* result_name(VkResult result);

// Throws rtsdf::Error naming the failing call and its result.
#define VK_CHECK(call)                                                                          \
  do {                                                                                          \
    VkResult vk_check_result_ = (call);                                                         \
    if (vk_check_result_ != VK_SUCCESS)                                                         \
      throw ::rtsdf::Error(std::string(#call " failed: ") + ::rtsdf::vk::result_name(vk_check_result_)); \
  } while (0)

struct ContextOptions {
  // Enable VK_LAYER_KHRONOS_validation and count its messages. Defaults to the
  // RTSDF_VALIDATION environment variable being set to a non-zero value.
  bool validation = false;
  // Substring of the device name to pick; empty = prefer a discrete/integrated
  // GPU, else the CPU driver. Defaults to the RTSDF_DEVICE environment variable.
  std::string device_name;

  static ContextOptions from_environment();
};

struct DeviceInfo {
  std::string name;
  std::string type;  // "discrete-gpu", "integrated-gpu", "cpu", ...
  std::string api_version;
  std::string driver;
};

class Context {
 public:
  explicit Context(const ContextOptions& options = ContextOptions::from_environment());
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  const DeviceInfo& info() const { return info_; }
  const VkPhysicalDeviceLimits& limits() const { return properties_.limits; }
  // Nanoseconds per timestamp tick; 0 when the queue has no timestamps.
  double timestamp_period_ns() const { return timestamp_period_ns_; }
  // Largest device-local heap in bytes.
  VkDeviceSize device_local_heap_bytes() const;
  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags flags) const;

  // Records commands into a one-time command buffer, submits and waits.
  void submit_and_wait(const std::function<void(VkCommandBuffer)>& record) const;

  // The object kept under `key`, made by `make` on the first call: objects
  // every user of the context shares (compiled pipelines, see vk::Pipeline),
  // kept until the context goes.
  std::shared_ptr<const void> shared(const std::string& key,
                                     const std::function<std::shared_ptr<const void>()>& make) const;
  size_t shared_object_count() const;

  // Validation messages (warnings and errors) seen since creation.
  int validation_message_count() const { return validation_messages_.load(); }

  // Names of all devices the loader sees, without creating a device.
  static std::vector<DeviceInfo> list_devices();

 private:
  void release();
  static VKAPI_ATTR VkBool32 VKAPI_CALL on_validation_message(
      VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
      const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  // Extension entry points belong to this instance, not to volk's globals,
  // which the next Context to be created reloads.
  PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger_ = nullptr;
  VkPhysicalDevice physical_device_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  mutable std::mutex submit_mutex_;
  mutable std::mutex shared_mutex_;
  mutable std::map<std::string, std::shared_ptr<const void>> shared_;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  DeviceInfo info_;
  double timestamp_period_ns_ = 0.0;
  std::atomic<int> validation_messages_{0};  // (messages arrive on whichever thread submits)
};

}  // namespace rtsdf::vk
