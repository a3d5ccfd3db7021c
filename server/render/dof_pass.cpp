#include "render/dof_pass.h"

#include <shared/frame.h>

#include <stdexcept>

namespace hdof {

DofComputePass::DofComputePass(const gpu::Context& context, const std::string& shaderName,
                               std::initializer_list<gpu::LayoutBinding> bindings)
    : context_(context),
      name_(shaderName),
      imageCount_(bindings.size() - 1),
      pipeline_(gpu::createComputePipeline(context, shaderName, VK_NULL_HANDLE, bindings)) {}

void DofComputePass::dispatch(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                              std::initializer_list<const gpu::Image*> images, uint32_t width,
                              uint32_t height, uint32_t groupSize) const {
  if (images.size() != imageCount_)
    throw std::logic_error(name_ + ": " + std::to_string(images.size()) + " images bound, " +
                           std::to_string(imageCount_) + " declared");
  gpu::DescriptorWriter writer;
  writer.uniformBuffer(gpu::kBindingFrame, frameUniforms);
  uint32_t binding = gpu::kBindingFrame + 1;
  for (const gpu::Image* image : images) writer.storageImage(binding++, *image);
  gpu::dispatchCompute(context_, cmd, pipeline_, writer, width, height, groupSize);
}

}  // namespace hdof
