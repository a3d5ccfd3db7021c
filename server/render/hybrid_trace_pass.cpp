#include "render/hybrid_trace_pass.h"

#include <shared/frame.h>

namespace hdof {

HybridTraceLayers::HybridTraceLayers(const gpu::Context& context, uint32_t width, uint32_t height) {
  constexpr VkImageUsageFlags kUse =
      VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  nearLayer = gpu::createImage2D(context, width, height, VK_FORMAT_R16G16B16A16_SFLOAT, kUse,
                                 "hybrid near layer");
  farLayer = gpu::createImage2D(context, width, height, VK_FORMAT_R16G16B16A16_SFLOAT, kUse,
                                "hybrid far layer");
  farPosition = gpu::createImage2D(context, width, height, VK_FORMAT_R32G32B32A32_SFLOAT, kUse,
                                   "hybrid far position");
  layerCoc =
      gpu::createImage2D(context, width, height, VK_FORMAT_R16G16_SFLOAT, kUse, "hybrid layer coc");
  samplesTraced = gpu::createImage2D(context, width, height, VK_FORMAT_R32_UINT,
                                     VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                     "hybrid samples traced");
  gpu::makeGeneral(context, {&nearLayer, &farLayer, &farPosition, &layerCoc, &samplesTraced});
  context.submitAndWait([&](VkCommandBuffer cmd) { gpu::clearToZero(cmd, {&samplesTraced}); });
}

HybridTracePass::HybridTracePass(const gpu::Context& context, const GpuScene& scene)
    : context_(context),
      scene_(scene),
      pipeline_(gpu::createComputePipeline(context, "hybrid_trace.comp", scene.setLayout(),
                                           {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
                                            {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                            {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                                            {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                                            {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                                            {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                                            {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}})) {}

void HybridTracePass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                             const gpu::Buffer& workList, const HybridTraceLayers& layers) const {
  scene_.bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.layout);
  // The work list starts with a VkDispatchIndirectCommand sized to its entries.
  gpu::dispatchComputeIndirect(context_, cmd, pipeline_,
                               gpu::DescriptorWriter()
                                   .uniformBuffer(gpu::kBindingFrame, frameUniforms)
                                   .storageBuffer(1, workList)
                                   .storageImage(2, layers.nearLayer)
                                   .storageImage(3, layers.farLayer)
                                   .storageImage(4, layers.farPosition)
                                   .storageImage(5, layers.layerCoc)
                                   .storageImage(6, layers.samplesTraced),
                               workList);
}

}  // namespace hdof
