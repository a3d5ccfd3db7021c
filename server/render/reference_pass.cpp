#include "render/reference_pass.h"

#include <shared/frame.h>

namespace hdof {

struct ReferencePush {
  uint32_t firstSample;
  uint32_t sampleCount;
  uint32_t accumulate;
};

ReferencePass::ReferencePass(const gpu::Context& context, const GpuScene& scene)
    : context_(context),
      scene_(scene),
      pipeline_(gpu::createComputePipeline(
          context, "reference.comp", scene.setLayout(),
          {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER}, {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}},
          sizeof(ReferencePush))) {}

void ReferencePass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                           const RenderTargets& targets, uint32_t firstSample,
                           uint32_t sampleCount, bool accumulate) const {
  scene_.bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.layout);
  ReferencePush push{firstSample, sampleCount, accumulate ? 1u : 0u};
  gpu::dispatchCompute(context_, cmd, pipeline_,
                       gpu::DescriptorWriter()
                           .uniformBuffer(gpu::kBindingFrame, frameUniforms)
                           .storageImage(1, targets.accumulation),
                       targets.width, targets.height, 8, &push);
}

}  // namespace hdof
