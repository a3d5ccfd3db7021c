#include "render/ray_mask_rays.h"

#include "render/dof_pass.h"

#include <shared/frame.h>

namespace hdof {

RayMaskRaysPass::RayMaskRaysPass(const gpu::Context& context)
    : context_(context),
      pipeline_(gpu::createComputePipeline(context, "ray_mask_rays.comp", VK_NULL_HANDLE,
                                           {kDofUniforms,
                                            kDofImage,
                                            kDofImage,
                                            {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
                                            kDofImage},
                                           sizeof(uint32_t))),
      sampler_(gpu::createNearestSampler(context)) {}

void RayMaskRaysPass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                             const gpu::Image& spread, const gpu::Image& dilatedTiles,
                             const gpu::Image& variance, const gpu::Image& rays,
                             bool everywhere) const {
  gpu::DescriptorWriter writer;
  writer.uniformBuffer(gpu::kBindingFrame, frameUniforms)
      .storageImage(1, spread)
      .storageImage(2, dilatedTiles)
      .sampledImage(3, variance, sampler_)
      .storageImage(4, rays);
  uint32_t everywhereFlag = everywhere ? 1u : 0u;
  gpu::dispatchCompute(context_, cmd, pipeline_, writer, rays.width(), rays.height(), 8,
                       &everywhereFlag);
}

}  // namespace hdof
