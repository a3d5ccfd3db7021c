#include "render/hybrid_composite_pass.h"

#include <shared/frame.h>

namespace hdof {

HybridCompositePass::HybridCompositePass(const gpu::Context& context)
    : context_(context), sampler_(gpu::createNearestSampler(context)) {
  constexpr VkDescriptorType kSampled = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  pipeline_ = gpu::createComputePipeline(context, "hybrid_composite.comp", VK_NULL_HANDLE,
                                         {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}});
}

void HybridCompositePass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                                 const gpu::Image& rays, const RenderTargets& targets,
                                 const gpu::Image& postProcess, const gpu::Image& nearLayer,
                                 const gpu::Image& farLayer, const gpu::Image& output) const {
  gpu::dispatchCompute(context_, cmd, pipeline_,
                       gpu::DescriptorWriter()
                           .uniformBuffer(gpu::kBindingFrame, frameUniforms)
                           .sampledImage(1, rays, sampler_)
                           .sampledImage(2, targets.color, sampler_)
                           .sampledImage(3, targets.specular, sampler_)
                           .sampledImage(4, targets.normalDepth, sampler_)
                           .sampledImage(5, postProcess, sampler_)
                           .sampledImage(6, nearLayer, sampler_)
                           .sampledImage(7, farLayer, sampler_)
                           .storageImage(8, output),
                       targets.width, targets.height);
}

}  // namespace hdof
