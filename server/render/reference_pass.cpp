#include "render/reference_pass.h"

#include <shared/frame.h>

namespace hdof {

struct ReferencePush {
  uint32_t firstSample;
  uint32_t sampleCount;
  uint32_t accumulate;
  uint32_t sequence;
};

ReferencePass::ReferencePass(const gpu::Context& context, const GpuScene& scene)
    : context_(context),
      scene_(scene),
      pipeline_(gpu::createComputePipeline(
          context, "reference.comp", scene.setLayout(),
          {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER}, {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}},
          sizeof(ReferencePush))) {}

void ReferencePass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                           const RenderTargets& targets, const Rays& rays) const {
  scene_.bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.layout);
  ReferencePush push{rays.firstSample, rays.count, rays.accumulate ? 1u : 0u, rays.sequence};
  gpu::dispatchCompute(context_, cmd, pipeline_,
                       gpu::DescriptorWriter()
                           .uniformBuffer(gpu::kBindingFrame, frameUniforms)
                           .storageImage(1, targets.accumulation),
                       targets.width, targets.height, 8, &push);
}

}  // namespace hdof
