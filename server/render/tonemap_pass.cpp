#include "render/tonemap_pass.h"

#include <shared/frame.h>

namespace hdof {

TonemapPass::TonemapPass(const gpu::Context& context)
    : context_(context),
      pipeline_(gpu::createComputePipeline(context, "tonemap.comp", VK_NULL_HANDLE,
                                           {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
                                            {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
                                            {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}})),
      sampler_(gpu::createNearestSampler(context)) {}

void TonemapPass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                         const gpu::Image& radiance, const RenderTargets& targets) const {
  gpu::dispatchCompute(context_, cmd, pipeline_,
                       gpu::DescriptorWriter()
                           .uniformBuffer(gpu::kBindingFrame, frameUniforms)
                           .sampledImage(1, radiance, sampler_)
                           .storageImage(2, targets.display),
                       targets.width, targets.height);
  gpu::copyImageToBuffer(cmd, targets.display, targets.readback);
}

}  // namespace hdof
