#include "render/render_targets.h"

namespace hdof {
namespace {

gpu::Image makeTarget(const gpu::Context& context, uint32_t width, uint32_t height, VkFormat format,
                      VkImageUsageFlags usage, const char* name) {
  gpu::ImageDesc desc;
  desc.width = width;
  desc.height = height;
  desc.format = format;
  desc.usage = usage;
  return gpu::Image(context, desc, name);
}

}  // namespace

RenderTargets::RenderTargets(const gpu::Context& context, uint32_t w, uint32_t h)
    : width(w), height(h) {
  constexpr VkImageUsageFlags kShaderUse = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
  constexpr VkImageUsageFlags kAttachment = kShaderUse | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
  visibility = makeTarget(context, w, h, VK_FORMAT_R32_UINT, kAttachment, "visibility");
  color = makeTarget(context, w, h, VK_FORMAT_R16G16B16A16_SFLOAT, kShaderUse, "color");
  specular = makeTarget(context, w, h, VK_FORMAT_R16G16B16A16_SFLOAT, kShaderUse, "specular");
  normalDepth = makeTarget(context, w, h, VK_FORMAT_R32G32B32A32_SFLOAT,
                           kShaderUse | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, "normal depth");
  accumulation =
      makeTarget(context, w, h, VK_FORMAT_R32G32B32A32_SFLOAT, kShaderUse, "accumulation");
  display = makeTarget(context, w, h, VK_FORMAT_R8G8B8A8_UNORM,
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

  context.submitAndWait([&](VkCommandBuffer cmd) {
    for (const gpu::Image* image :
         {&visibility, &color, &specular, &normalDepth, &accumulation, &display})
      gpu::transitionImage(cmd, image->get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                           VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                           VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  });
}

}  // namespace hdof
