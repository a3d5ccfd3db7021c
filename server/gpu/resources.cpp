#include "gpu/resources.h"

#include <bit>

namespace hdof::gpu {
namespace {

DeviceMemory allocate(const Context& context, const VkMemoryRequirements& requirements,
                      VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) {
  VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  info.allocationSize = requirements.size;
  info.memoryTypeIndex = context.findMemoryType(requirements.memoryTypeBits, required, preferred);
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VK_CHECK(vkAllocateMemory(context.device(), &info, nullptr, &memory));
  return DeviceMemory(context.device(), memory);
}

}  // namespace

Fence createFence(const Context& context, bool signaled) {
  VkFenceCreateInfo info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  if (signaled) info.flags = VK_FENCE_CREATE_SIGNALED_BIT;
  VkFence fence = VK_NULL_HANDLE;
  VK_CHECK(vkCreateFence(context.device(), &info, nullptr, &fence));
  return Fence(context.device(), fence);
}

Buffer::Buffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use,
               const std::string& name)
    : size_(size) {
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkBuffer buffer = VK_NULL_HANDLE;
  VK_CHECK(vkCreateBuffer(context.device(), &info, nullptr, &buffer));
  buffer_ = BufferHandle(context.device(), buffer);
  context.setName(VK_OBJECT_TYPE_BUFFER, reinterpret_cast<uint64_t>(buffer), name);

  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(context.device(), buffer, &requirements);
  VkMemoryPropertyFlags required = 0, preferred = 0;
  switch (use) {
    case MemoryUse::DeviceOnly:
      preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
      break;
    case MemoryUse::Upload:
      required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
      break;
    case MemoryUse::Readback:
      required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
      preferred = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
      break;
  }
  memory_ = allocate(context, requirements, required, preferred);
  VK_CHECK(vkBindBufferMemory(context.device(), buffer, memory_, 0));
  if (use != MemoryUse::DeviceOnly)
    VK_CHECK(vkMapMemory(context.device(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
}

Buffer createBufferWithData(const Context& context, std::span<const std::byte> bytes,
                            VkBufferUsageFlags usage, const std::string& name) {
  VkDeviceSize size = std::max<VkDeviceSize>(bytes.size(), 16);
  Buffer buffer(context, size, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::DeviceOnly,
                name);
  if (!bytes.empty()) {
    Buffer staging(context, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload,
                   name + " staging");
    std::memcpy(staging.mapped(), bytes.data(), bytes.size());
    context.submitAndWait([&](VkCommandBuffer cmd) {
      VkBufferCopy region{0, 0, bytes.size()};
      vkCmdCopyBuffer(cmd, staging.get(), buffer.get(), 1, &region);
    });
  }
  return buffer;
}

Image::Image(const Context& context, const ImageDesc& desc, const std::string& name) : desc_(desc) {
  auto allocated = [&](uint32_t side) {
    if (!desc.sidesOffPowerOfTwo) return side;
    while (std::has_single_bit(side)) ++side;
    return side;
  };
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = desc.format;
  allocated_ = {allocated(desc.width), allocated(desc.height)};
  info.extent = {allocated_.width, allocated_.height, 1};
  info.mipLevels = desc.mipLevels;
  info.arrayLayers = desc.layers;
  info.samples = desc.samples;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = desc.usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkImage image = VK_NULL_HANDLE;
  VK_CHECK(vkCreateImage(context.device(), &info, nullptr, &image));
  image_ = ImageHandle(context.device(), image);
  context.setName(VK_OBJECT_TYPE_IMAGE, reinterpret_cast<uint64_t>(image), name);

  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(context.device(), image, &requirements);
  memory_ = allocate(context, requirements, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  VK_CHECK(vkBindImageMemory(context.device(), image, memory_, 0));

  VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  viewInfo.image = image;
  viewInfo.viewType =
      desc.layers > 1 || desc.arrayView ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
  viewInfo.format = desc.format;
  viewInfo.subresourceRange = {desc.aspect, 0, desc.mipLevels, 0, desc.layers};
  VkImageView view = VK_NULL_HANDLE;
  VK_CHECK(vkCreateImageView(context.device(), &viewInfo, nullptr, &view));
  view_ = ImageView(context.device(), view);
  context.setName(VK_OBJECT_TYPE_IMAGE_VIEW, reinterpret_cast<uint64_t>(view), name + " view");
}

Image createImage2D(const Context& context, uint32_t width, uint32_t height, VkFormat format,
                    VkImageUsageFlags usage, const std::string& name) {
  ImageDesc desc;
  desc.width = width;
  desc.height = height;
  desc.format = format;
  desc.usage = usage;
  return Image(context, desc, name);
}

Image ImageBatch::make(uint32_t width, uint32_t height, VkFormat format, const std::string& name,
                       VkImageUsageFlags extraUsage) {
  constexpr VkImageUsageFlags kUsage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                       VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                       VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  ImageDesc desc;
  desc.width = width;
  desc.height = height;
  desc.format = format;
  desc.usage = kUsage | extraUsage;
  return make(desc, name);
}

Image ImageBatch::make(const ImageDesc& desc, const std::string& name) {
  ImageDesc padded = desc;
  padded.sidesOffPowerOfTwo = true;
  Image image(context_, padded, name);
  made_.push_back(image.get());
  return image;
}

void ImageBatch::finish() {
  context_.submitAndWait([&](VkCommandBuffer cmd) {
    VkClearColorValue zero{};
    VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    for (VkImage image : made_) {
      transitionImage(cmd, image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_ACCESS_TRANSFER_WRITE_BIT);
      vkCmdClearColorImage(cmd, image, VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &range);
    }
    memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                  VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                  VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT);
  });
  made_.clear();
}

void copyImageToBuffer(VkCommandBuffer cmd, const Image& image, const Buffer& buffer) {
  memoryBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT,
                VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {image.width(), image.height(), 1};
  vkCmdCopyImageToBuffer(cmd, image.get(), VK_IMAGE_LAYOUT_GENERAL, buffer.get(), 1, &region);
  memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
}

void copyImage(VkCommandBuffer cmd, const Image& source, const Image& destination) {
  VkImageCopy region{};
  region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.dstSubresource = region.srcSubresource;
  region.extent = {source.width(), source.height(), 1};
  vkCmdCopyImage(cmd, source.get(), VK_IMAGE_LAYOUT_GENERAL, destination.get(),
                 VK_IMAGE_LAYOUT_GENERAL, 1, &region);
}

void copyBufferToHost(VkCommandBuffer cmd, const Buffer& source, const Buffer& destination,
                      VkDeviceSize bytes) {
  memoryBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT,
                VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  VkBufferCopy region{0, 0, bytes};
  vkCmdCopyBuffer(cmd, source.get(), destination.get(), 1, &region);
  memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
}

void transitionImage(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                     VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                     VkPipelineStageFlags dstStage, VkAccessFlags dstAccess,
                     VkImageAspectFlags aspect) {
  VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  barrier.srcAccessMask = srcAccess;
  barrier.dstAccessMask = dstAccess;
  barrier.oldLayout = from;
  barrier.newLayout = to;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image;
  barrier.subresourceRange = {aspect, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
  vkCmdPipelineBarrier(cmd, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &barrier);
}

void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                   VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) {
  VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  barrier.srcAccessMask = srcAccess;
  barrier.dstAccessMask = dstAccess;
  vkCmdPipelineBarrier(cmd, srcStage, dstStage, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

}  // namespace hdof::gpu
