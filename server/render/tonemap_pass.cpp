#include "render/tonemap_pass.h"

#include <shared/frame.h>

namespace hdof {

TonemapPass::TonemapPass(const gpu::Context& context)
    : context_(context),
      pipeline_(gpu::createComputePipeline(context, "tonemap.comp", VK_NULL_HANDLE,
                                           {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
                                            {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
                                            {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}})) {
  VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  info.magFilter = info.minFilter = VK_FILTER_NEAREST;
  info.addressModeU = info.addressModeV = info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  VkSampler sampler = VK_NULL_HANDLE;
  VK_CHECK(vkCreateSampler(context.device(), &info, nullptr, &sampler));
  sampler_ = gpu::Sampler(context.device(), sampler);
}

void TonemapPass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                         const gpu::Image& radiance, const RenderTargets& targets) const {
  gpu::dispatchCompute(context_, cmd, pipeline_,
                       gpu::DescriptorWriter()
                           .uniformBuffer(gpu::kBindingFrame, frameUniforms)
                           .sampledImage(1, radiance, sampler_)
                           .storageImage(2, targets.display),
                       targets.width, targets.height);
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {targets.width, targets.height, 1};
  vkCmdCopyImageToBuffer(cmd, targets.display.get(), VK_IMAGE_LAYOUT_GENERAL,
                         targets.readback.get(), 1, &region);
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
}

}  // namespace hdof
