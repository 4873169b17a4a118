#pragma once
// Owned device resources. Each object frees what it allocated; nothing is
// destroyed by hand at call sites.
#include <volk.h>

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <vector>
#include <glm/glm.hpp>

namespace rtsdf::vk {

class Context;

class Buffer {
 public:
  enum class Access { DeviceOnly, HostVisible };
  Buffer() = default;
  Buffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage, Access access);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  void* mapped() const { return mapped_; }  // host-visible buffers only
  // Where shaders reach it through a buffer reference (buffers made with
  // VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT only; 0 otherwise).
  VkDeviceAddress device_address() const { return address_; }
  explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }

 private:
  void release();
  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
  VkDeviceAddress address_ = 0;
};

// A device image: a volume (dims.z > 1, e.g. seeds or distances) or a plane
// (dims.z == 1, e.g. G-buffer targets). Depth formats get a depth view.
class Image {
 public:
  Image() = default;
  Image(const Context& context, glm::ivec3 dims, VkFormat format, VkImageUsageFlags usage);
  static Image plane(const Context& context, int width, int height, VkFormat format, VkImageUsageFlags usage);
  ~Image();
  Image(Image&& other) noexcept;
  Image& operator=(Image&& other) noexcept;
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;

  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }
  glm::ivec3 dims() const { return dims_; }
  VkFormat format() const { return format_; }
  VkDeviceSize texel_count() const { return VkDeviceSize(dims_.x) * dims_.y * dims_.z; }

 private:
  void release();
  VkDevice device_ = VK_NULL_HANDLE;
  VkImage image_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  glm::ivec3 dims_{0};
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  bool volume_ = true;
};

// Uploads host data into a new device-local buffer through a staging copy.
Buffer upload_buffer(const Context& context, const void* data, VkDeviceSize size, VkBufferUsageFlags usage);
// Overwrites of ranges of device-local buffers (made with TRANSFER_DST
// usage, as upload_buffer's are), after the work submitted before has read
// them and before any work submitted after reads them: gathered and made in
// one submission through one staging buffer (each submission waits for the
// device: a deformed mesh's ranges were nine of them a frame).
class BufferWrites {
 public:
  // Copies `data` now; written by submit().
  void add(const Buffer& buffer, VkDeviceSize offset, const void* data, VkDeviceSize size);
  template <typename T>
  void add_range(const Buffer& buffer, size_t first, const std::vector<T>& items) {
    add(buffer, first * sizeof(T), items.data(), items.size() * sizeof(T));
  }
  void submit(const Context& context);

 private:
  struct Write {
    VkBuffer buffer;
    VkDeviceSize offset, size, staged;  // (staged: where its bytes start in the staging buffer)
  };
  std::vector<Write> writes_;
  std::vector<uint8_t> bytes_;
};

// Barrier helpers for the common "previous writes visible to next reads" case.
void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                   VkAccessFlags src_access, VkAccessFlags dst_access, VkPipelineStageFlags src_stage,
                   VkPipelineStageFlags dst_stage);
void memory_barrier(VkCommandBuffer cmd, VkAccessFlags src_access, VkAccessFlags dst_access,
                    VkPipelineStageFlags src_stage, VkPipelineStageFlags dst_stage);
// What compute or fragment shaders wrote, visible to the next compute pass's reads and writes.
void shader_writes_to_compute(VkCommandBuffer cmd);

// Moves freshly created colour images into GENERAL, the layout every pass
// uses them in (storage images), before any pass touches them.
void make_general(const Context& context, std::initializer_list<const Image*> images);

// Copies a whole colour image (in GENERAL layout) into a host-visible buffer and returns it.
Buffer download_image(const Context& context, const Image& image, VkDeviceSize bytes_per_texel);
// Copies whole colour images of `bytes_per_texel` (in GENERAL layout) one
// after the other into `staging`, in one submission, and returns where each
// starts. `staging` is (re)made host-visible where it is too small, else
// reused: a caller that reads every frame (a viewport) keeps it, as a new
// buffer's pages cost more to touch than the copy itself.
std::vector<VkDeviceSize> download_images(const Context& context, std::initializer_list<const Image*> images,
                                          VkDeviceSize bytes_per_texel, Buffer& staging);

}  // namespace rtsdf::vk
