#include "vk/resources.h"

#include <cstring>
#include <utility>

#include "vk/context.h"

namespace rtsdf::vk {

namespace {

VkDeviceMemory allocate(const Context& context, const VkMemoryRequirements& requirements,
                        VkMemoryPropertyFlags flags, bool device_address = false) {
  VkMemoryAllocateFlagsInfo address_info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
  address_info.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  if (device_address) info.pNext = &address_info;
  info.allocationSize = requirements.size;
  info.memoryTypeIndex = context.memory_type(requirements.memoryTypeBits, flags);
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkResult result = vkAllocateMemory(context.device(), &info, nullptr, &memory);
  if (result != VK_SUCCESS)
    throw Error("could not allocate " + std::to_string(requirements.size >> 20) + " MiB on the Vulkan device (" +
                result_name(result) + "): lower the resolution");
  return memory;
}

}  // namespace

Buffer::Buffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage, Access access)
    : device_(context.device()), size_(size) {
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size > 0 ? size : 4;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VK_CHECK(vkCreateBuffer(device_, &info, nullptr, &buffer_));
  try {
    VkMemoryRequirements requirements;
    vkGetBufferMemoryRequirements(device_, buffer_, &requirements);
    VkMemoryPropertyFlags flags = access == Access::HostVisible
                                      ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                                      : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    const bool addressed = (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) != 0;
    memory_ = allocate(context, requirements, flags, addressed);
    VK_CHECK(vkBindBufferMemory(device_, buffer_, memory_, 0));
    if (addressed) {
      VkBufferDeviceAddressInfo address{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
      address.buffer = buffer_;
      address_ = vkGetBufferDeviceAddress(device_, &address);
    }
    if (access == Access::HostVisible) VK_CHECK(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
  } catch (...) {
    release();
    throw;
  }
}

Buffer::~Buffer() { release(); }

Buffer::Buffer(Buffer&& other) noexcept { *this = std::move(other); }

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    release();
    device_ = std::exchange(other.device_, VK_NULL_HANDLE);
    buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    size_ = std::exchange(other.size_, 0);
    mapped_ = std::exchange(other.mapped_, nullptr);
    address_ = std::exchange(other.address_, 0);
  }
  return *this;
}

void Buffer::release() {
  if (buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
  if (memory_) vkFreeMemory(device_, memory_, nullptr);  // also unmaps
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
  address_ = 0;
}

namespace {
bool is_depth(VkFormat format) {
  return format == VK_FORMAT_D32_SFLOAT || format == VK_FORMAT_D16_UNORM || format == VK_FORMAT_D24_UNORM_S8_UINT ||
         format == VK_FORMAT_D32_SFLOAT_S8_UINT;
}
}  // namespace

Image Image::plane(const Context& context, int width, int height, VkFormat format, VkImageUsageFlags usage) {
  return Image(context, glm::ivec3(width, height, 1), format, usage);
}

Image::Image(const Context& context, glm::ivec3 dims, VkFormat format, VkImageUsageFlags usage)
    : device_(context.device()), dims_(dims), format_(format), volume_(dims.z > 1) {
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = volume_ ? VK_IMAGE_TYPE_3D : VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {uint32_t(dims.x), uint32_t(dims.y), uint32_t(dims.z)};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VK_CHECK(vkCreateImage(device_, &info, nullptr, &image_));
  try {
    VkMemoryRequirements requirements;
    vkGetImageMemoryRequirements(device_, image_, &requirements);
    memory_ = allocate(context, requirements, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    VK_CHECK(vkBindImageMemory(device_, image_, memory_, 0));
    VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    view.image = image_;
    view.viewType = volume_ ? VK_IMAGE_VIEW_TYPE_3D : VK_IMAGE_VIEW_TYPE_2D;
    view.format = format;
    view.subresourceRange = {VkImageAspectFlags(is_depth(format) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT),
                             0, 1, 0, 1};
    VK_CHECK(vkCreateImageView(device_, &view, nullptr, &view_));
  } catch (...) {
    release();
    throw;
  }
}

Image::~Image() { release(); }

Image::Image(Image&& other) noexcept { *this = std::move(other); }

Image& Image::operator=(Image&& other) noexcept {
  if (this != &other) {
    release();
    device_ = std::exchange(other.device_, VK_NULL_HANDLE);
    image_ = std::exchange(other.image_, VK_NULL_HANDLE);
    view_ = std::exchange(other.view_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    dims_ = std::exchange(other.dims_, glm::ivec3(0));
    format_ = std::exchange(other.format_, VK_FORMAT_UNDEFINED);
    volume_ = other.volume_;
  }
  return *this;
}

void Image::release() {
  if (view_) vkDestroyImageView(device_, view_, nullptr);
  if (image_) vkDestroyImage(device_, image_, nullptr);
  if (memory_) vkFreeMemory(device_, memory_, nullptr);
  view_ = VK_NULL_HANDLE;
  image_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
}

Buffer upload_buffer(const Context& context, const void* data, VkDeviceSize size, VkBufferUsageFlags usage) {
  Buffer staging(context, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, Buffer::Access::HostVisible);
  if (size > 0) std::memcpy(staging.mapped(), data, size);
  Buffer buffer(context, size, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, Buffer::Access::DeviceOnly);
  if (size > 0)
    context.submit_and_wait([&](VkCommandBuffer cmd) {
      VkBufferCopy region{0, 0, size};
      vkCmdCopyBuffer(cmd, staging.handle(), buffer.handle(), 1, &region);
    });
  return buffer;
}

void BufferWrites::add(const Buffer& buffer, VkDeviceSize offset, const void* data, VkDeviceSize size) {
  if (size == 0) return;
  if (offset + size > buffer.size()) throw Error("BufferWrites: the range ends past the buffer");
  writes_.push_back({buffer.handle(), offset, size, bytes_.size()});
  const uint8_t* from = static_cast<const uint8_t*>(data);
  bytes_.insert(bytes_.end(), from, from + size);
}

void BufferWrites::submit(const Context& context) {
  if (writes_.empty()) return;
  Buffer staging(context, bytes_.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, Buffer::Access::HostVisible);
  std::memcpy(staging.mapped(), bytes_.data(), bytes_.size());
  context.submit_and_wait([&](VkCommandBuffer cmd) {
    memory_barrier(cmd, VK_ACCESS_MEMORY_READ_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                   VK_PIPELINE_STAGE_TRANSFER_BIT);
    for (const Write& write : writes_) {
      VkBufferCopy region{write.staged, write.offset, write.size};
      vkCmdCopyBuffer(cmd, staging.handle(), write.buffer, 1, &region);
    }
    memory_barrier(cmd, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_MEMORY_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                   VK_PIPELINE_STAGE_ALL_COMMANDS_BIT);
  });
  writes_.clear();
  bytes_.clear();
}

void make_general(const Context& context, std::initializer_list<const Image*> images) {
  context.submit_and_wait([&](VkCommandBuffer cmd) {
    for (const Image* image : images)
      image_barrier(cmd, image->handle(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, 0,
                    VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT);
  });
}

void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                   VkAccessFlags src_access, VkAccessFlags dst_access, VkPipelineStageFlags src_stage,
                   VkPipelineStageFlags dst_stage) {
  VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  barrier.srcAccessMask = src_access;
  barrier.dstAccessMask = dst_access;
  barrier.oldLayout = from;
  barrier.newLayout = to;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image;
  barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 0, nullptr, 0, nullptr, 1, &barrier);
}

void memory_barrier(VkCommandBuffer cmd, VkAccessFlags src_access, VkAccessFlags dst_access,
                    VkPipelineStageFlags src_stage, VkPipelineStageFlags dst_stage) {
  VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  barrier.srcAccessMask = src_access;
  barrier.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

void shader_writes_to_compute(VkCommandBuffer cmd) {
  memory_barrier(cmd, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
}

Buffer download_image(const Context& context, const Image& image, VkDeviceSize bytes_per_texel) {
  Buffer readback;
  download_images(context, {&image}, bytes_per_texel, readback);
  return readback;
}

std::vector<VkDeviceSize> download_images(const Context& context, std::initializer_list<const Image*> images,
                                          VkDeviceSize bytes_per_texel, Buffer& staging) {
  std::vector<VkDeviceSize> offsets;
  VkDeviceSize total = 0;
  for (const Image* image : images) offsets.push_back(total), total += image->texel_count() * bytes_per_texel;
  if (!staging.handle() || staging.size() < total)
    staging = Buffer(context, total, VK_BUFFER_USAGE_TRANSFER_DST_BIT, Buffer::Access::HostVisible);
  context.submit_and_wait([&](VkCommandBuffer cmd) {
    size_t i = 0;
    for (const Image* image : images) {
      image_barrier(cmd, image->handle(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                    VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT,
                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                    VK_PIPELINE_STAGE_TRANSFER_BIT);
      VkBufferImageCopy region{};
      region.bufferOffset = offsets[i++];
      region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
      region.imageExtent = {uint32_t(image->dims().x), uint32_t(image->dims().y), uint32_t(image->dims().z)};
      vkCmdCopyImageToBuffer(cmd, image->handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.handle(), 1, &region);
      image_barrier(cmd, image->handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                    VK_ACCESS_TRANSFER_READ_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                    VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT);
    }
    memory_barrier(cmd, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                   VK_PIPELINE_STAGE_HOST_BIT);
  });
  return offsets;
}

}  // namespace rtsdf::vk
