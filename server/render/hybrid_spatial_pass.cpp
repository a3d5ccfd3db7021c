#include "render/hybrid_spatial_pass.h"

#include <shared/frame.h>

namespace hdof {
namespace {

std::unique_ptr<gpu::Image> makeLayer(const gpu::Context& context, uint32_t w, uint32_t h,
                                      const char* name) {
  return gpu::createGeneralImage2D(
      context, w, h, VK_FORMAT_R16G16B16A16_SFLOAT,
      VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
      name);
}

}  // namespace

HybridSpatialPass::HybridSpatialPass(const gpu::Context& context, uint32_t width, uint32_t height)
    : context_(context), sampler_(gpu::createNearestSampler(context)) {
  constexpr VkDescriptorType kSampled = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  pipeline_ = gpu::createComputePipeline(context, "hybrid_spatial.comp", VK_NULL_HANDLE,
                                         {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
                                          {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                                          {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}});
  resize(width, height);
}

HybridSpatialPass::~HybridSpatialPass() = default;

void HybridSpatialPass::resize(uint32_t width, uint32_t height) {
  if (near_ && near_->width() == width && near_->height() == height) return;
  if (near_) VK_CHECK(vkQueueWaitIdle(context_.queue()));
  near_ = makeLayer(context_, width, height, "hybrid reconstructed near");
  far_ = makeLayer(context_, width, height, "hybrid reconstructed far");
}

void HybridSpatialPass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                               const gpu::Buffer& workList, const gpu::Image& rays,
                               const HybridTraceLayers& layers,
                               const HybridTemporalPass& temporal) const {
  const HybridTemporalPass::History& history = temporal.current();
  gpu::dispatchComputeIndirect(context_, cmd, pipeline_,
                               gpu::DescriptorWriter()
                                   .uniformBuffer(gpu::kBindingFrame, frameUniforms)
                                   .storageBuffer(1, workList)
                                   .sampledImage(2, rays, sampler_)
                                   .sampledImage(3, layers.layerCoc, sampler_)
                                   .sampledImage(4, history.nearLayer, sampler_)
                                   .sampledImage(5, history.farLayer, sampler_)
                                   .sampledImage(6, history.moments, sampler_)
                                   .sampledImage(7, temporal.variance(), sampler_)
                                   .storageImage(8, *near_)
                                   .storageImage(9, *far_),
                               workList);
}

}  // namespace hdof
