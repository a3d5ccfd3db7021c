#include "render/debug_view_pass.h"

#include <shared/frame.h>

namespace hdof {
DebugViewPass::DebugViewPass(const gpu::Context& context)
    : context_(context), sampler_(gpu::createNearestSampler(context)) {
  constexpr VkDescriptorType kSampled = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  pipeline_ = gpu::createComputePipeline(context, "debug_view.comp", VK_NULL_HANDLE,
                                         {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}},
                                         sizeof(uint32_t));
}

void DebugViewPass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, DebugView view,
                           const gpu::Image& rays, const RenderTargets& targets,
                           const gpu::Image& nearLayer, const gpu::Image& farLayer,
                           const gpu::Image& output) const {
  uint32_t viewIndex = static_cast<uint32_t>(view);
  gpu::dispatchCompute(context_, cmd, pipeline_,
                       gpu::DescriptorWriter()
                           .uniformBuffer(gpu::kBindingFrame, frameUniforms)
                           .sampledImage(1, rays, sampler_)
                           .sampledImage(2, targets.normalDepth, sampler_)
                           .sampledImage(3, nearLayer, sampler_)
                           .sampledImage(4, farLayer, sampler_)
                           .storageImage(5, output),
                       targets.width, targets.height, 8, &viewIndex);
}

}  // namespace hdof
