// Move-only owners of Vulkan objects: a generic device-object handle, buffers and images with
// their memory. Every object gets a debug name.
#pragma once

#include "gpu/context.h"

#include <cstring>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace hdof::gpu {

template <typename T, void (*Destroy)(VkDevice, T, const VkAllocationCallbacks*)>
class DeviceObject {
 public:
  DeviceObject() = default;
  DeviceObject(VkDevice device, T handle) : device_(device), handle_(handle) {}
  ~DeviceObject() { reset(); }
  DeviceObject(const DeviceObject&) = delete;
  DeviceObject& operator=(const DeviceObject&) = delete;
  DeviceObject(DeviceObject&& other) noexcept
      : device_(other.device_), handle_(std::exchange(other.handle_, VK_NULL_HANDLE)) {}
  DeviceObject& operator=(DeviceObject&& other) noexcept {
    if (this != &other) {
      reset();
      device_ = other.device_;
      handle_ = std::exchange(other.handle_, VK_NULL_HANDLE);
    }
    return *this;
  }
  void reset() {
    if (handle_ != VK_NULL_HANDLE) Destroy(device_, handle_, nullptr);
    handle_ = VK_NULL_HANDLE;
  }
  T get() const { return handle_; }
  operator T() const { return handle_; }
  explicit operator bool() const { return handle_ != VK_NULL_HANDLE; }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  T handle_ = VK_NULL_HANDLE;
};

using ShaderModule = DeviceObject<VkShaderModule, vkDestroyShaderModule>;
using PipelineLayout = DeviceObject<VkPipelineLayout, vkDestroyPipelineLayout>;
using Pipeline = DeviceObject<VkPipeline, vkDestroyPipeline>;
using DescriptorSetLayout = DeviceObject<VkDescriptorSetLayout, vkDestroyDescriptorSetLayout>;
using DescriptorPool = DeviceObject<VkDescriptorPool, vkDestroyDescriptorPool>;
using Sampler = DeviceObject<VkSampler, vkDestroySampler>;
using Fence = DeviceObject<VkFence, vkDestroyFence>;
using QueryPool = DeviceObject<VkQueryPool, vkDestroyQueryPool>;
using DeviceMemory = DeviceObject<VkDeviceMemory, vkFreeMemory>;
using BufferHandle = DeviceObject<VkBuffer, vkDestroyBuffer>;
using ImageHandle = DeviceObject<VkImage, vkDestroyImage>;
using ImageView = DeviceObject<VkImageView, vkDestroyImageView>;
using RenderPass = DeviceObject<VkRenderPass, vkDestroyRenderPass>;
using Framebuffer = DeviceObject<VkFramebuffer, vkDestroyFramebuffer>;
using BufferView = DeviceObject<VkBufferView, vkDestroyBufferView>;

Fence createFence(const Context& context, bool signaled = false);

enum class MemoryUse {
  DeviceOnly,  // GPU reads and writes
  Upload,      // the CPU writes through a persistent mapping, the GPU reads
  Readback,    // the GPU writes, the CPU reads through a persistent mapping
};

class Buffer {
 public:
  Buffer() = default;
  Buffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use,
         const std::string& name);
  VkBuffer get() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  void* mapped() const { return mapped_; }  // null for MemoryUse::DeviceOnly
  VkDescriptorBufferInfo descriptor() const { return {buffer_, 0, size_}; }

 private:
  BufferHandle buffer_;
  DeviceMemory memory_;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
};

// A device-local buffer filled with `bytes` through a staging copy.
Buffer createBufferWithData(const Context& context, std::span<const std::byte> bytes,
                            VkBufferUsageFlags usage, const std::string& name);

template <typename T>
Buffer createBufferWithData(const Context& context, std::span<const T> items,
                            VkBufferUsageFlags usage, const std::string& name) {
  return createBufferWithData(context, std::as_bytes(items), usage, name);
}

struct ImageDesc {
  uint32_t width = 1, height = 1, mipLevels = 1, layers = 1;
  bool arrayView = false;  // view as a 2D array (always when layers > 1)
  VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
  VkImageUsageFlags usage = VK_IMAGE_USAGE_STORAGE_BIT;
  VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT;
  VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;
  // Allocated with each side that is a power of two one texel longer (three for sides of one and
  // two), the extra texels unused: width and height stay the used part, which copies and
  // dispatches cover. llvmpipe compiles a shader again for images with such sides, and a frame
  // of some viewports makes them (a side of 1015 pixels is 64 tiles across).
  bool sidesOffPowerOfTwo = false;
};

class Image {
 public:
  Image() = default;
  Image(const Context& context, const ImageDesc& desc, const std::string& name);
  VkImage get() const { return image_; }
  VkImageView view() const { return view_; }
  const ImageDesc& desc() const { return desc_; }
  uint32_t width() const { return desc_.width; }
  uint32_t height() const { return desc_.height; }
  VkExtent2D allocated() const { return allocated_; }  // width and height, or more

 private:
  ImageHandle image_;
  DeviceMemory memory_;
  ImageView view_;
  ImageDesc desc_;
  VkExtent2D allocated_{};
};

// A single-level 2D colour image.
Image createImage2D(const Context& context, uint32_t width, uint32_t height, VkFormat format,
                    VkImageUsageFlags usage, const std::string& name);

// Makes the images of a frame pipeline (2D, single level, for storage, sampling and transfers;
// sidesOffPowerOfTwo, so that no viewport compiles shaders anew) and readies them in one
// submission: each moved to VK_IMAGE_LAYOUT_GENERAL, where it stays, and cleared to zero.
class ImageBatch {
 public:
  explicit ImageBatch(const Context& context) : context_(context) {}
  Image make(uint32_t width, uint32_t height, VkFormat format, const std::string& name,
             VkImageUsageFlags extraUsage = 0);
  // Any other colour image (a multisampled one, say), with the usage `desc` gives.
  Image make(const ImageDesc& desc, const std::string& name);
  // Submits and waits. The images made must still exist.
  void finish();

 private:
  const Context& context_;
  std::vector<VkImage> made_;
};

// Copies a single-level colour image in VK_IMAGE_LAYOUT_GENERAL to a host-readable buffer (tight
// rows), after all earlier writes and before the host reads it.
void copyImageToBuffer(VkCommandBuffer cmd, const Image& image, const Buffer& buffer);

// Copies a single-level colour image to another of the same size and format, both in
// VK_IMAGE_LAYOUT_GENERAL; ordering against other work is the caller's (a step's barrier).
void copyImage(VkCommandBuffer cmd, const Image& source, const Image& destination);

// Copies the first `bytes` of a buffer to a host-readable one, after all earlier writes and
// before the host reads it.
void copyBufferToHost(VkCommandBuffer cmd, const Buffer& source, const Buffer& destination,
                      VkDeviceSize bytes);

// One image layout transition (and execution/memory dependency) for all mip levels.
void transitionImage(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                     VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                     VkPipelineStageFlags dstStage, VkAccessFlags dstAccess,
                     VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT);

// A global memory barrier between passes (compute/graphics writes then reads).
void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                   VkPipelineStageFlags dstStage, VkAccessFlags dstAccess);

}  // namespace hdof::gpu
