#include "render/render_targets.h"

namespace hdof {
RenderTargets::RenderTargets(const gpu::Context& context, uint32_t w, uint32_t h)
    : width(w), height(h) {
  constexpr VkImageUsageFlags kShaderUse = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
  constexpr VkImageUsageFlags kAttachment = kShaderUse | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
  visibility = gpu::createImage2D(context, w, h, VK_FORMAT_R32_UINT, kAttachment, "visibility");
  color = gpu::createImage2D(context, w, h, VK_FORMAT_R16G16B16A16_SFLOAT, kShaderUse, "color");
  specular =
      gpu::createImage2D(context, w, h, VK_FORMAT_R16G16B16A16_SFLOAT, kShaderUse, "specular");
  normalDepth = gpu::createImage2D(context, w, h, VK_FORMAT_R32G32B32A32_SFLOAT,
                                   kShaderUse | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, "normal depth");
  motion = gpu::createImage2D(context, w, h, VK_FORMAT_R16G16_SFLOAT,
                              kShaderUse | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, "motion");
  accumulation =
      gpu::createImage2D(context, w, h, VK_FORMAT_R32G32B32A32_SFLOAT, kShaderUse, "accumulation");
  display = gpu::createImage2D(context, w, h, VK_FORMAT_R8G8B8A8_UNORM,
                               kShaderUse | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, "display");
  gpu::ImageDesc depthDesc;
  depthDesc.width = w;
  depthDesc.height = h;
  depthDesc.format = VK_FORMAT_D32_SFLOAT;
  depthDesc.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
  depthDesc.aspect = VK_IMAGE_ASPECT_DEPTH_BIT;
  depth = gpu::Image(context, depthDesc, "depth");
  readback = gpu::Buffer(context, VkDeviceSize(w) * h * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                         gpu::MemoryUse::Readback, "display readback");

  gpu::makeGeneral(
      context, {&visibility, &color, &specular, &normalDepth, &motion, &accumulation, &display});
}

}  // namespace hdof
