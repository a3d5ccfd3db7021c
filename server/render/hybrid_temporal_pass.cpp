#include "render/hybrid_temporal_pass.h"

#include <shared/frame.h>

namespace hdof {

struct HybridTemporalPass::Images {
  Images(const gpu::Context& context, uint32_t width, uint32_t height);
  uint32_t width, height;
  std::array<History, 2> history;
  gpu::Image variance;
  uint32_t written = 0;  // which history the last frame wrote
};

namespace {

struct TemporalPush {
  uint32_t reset;
  float minBlend;
};

HybridTemporalPass::History makeHistory(const gpu::Context& context, uint32_t w, uint32_t h) {
  constexpr VkImageUsageFlags kUse = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                     VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                     VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  return {
      gpu::createImage2D(context, w, h, VK_FORMAT_R16G16B16A16_SFLOAT, kUse, "history near"),
      gpu::createImage2D(context, w, h, VK_FORMAT_R16G16B16A16_SFLOAT, kUse, "history far"),
      gpu::createImage2D(context, w, h, VK_FORMAT_R32G32B32A32_SFLOAT, kUse, "history moments")};
}

}  // namespace

HybridTemporalPass::Images::Images(const gpu::Context& context, uint32_t w, uint32_t h)
    : width(w),
      height(h),
      history{makeHistory(context, w, h), makeHistory(context, w, h)},
      variance(gpu::createImage2D(context, w, h, VK_FORMAT_R16_SFLOAT,
                                  VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                      VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                      VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                  "hybrid variance")) {
  gpu::makeGeneral(context,
                   {&history[0].nearLayer, &history[0].farLayer, &history[0].moments,
                    &history[1].nearLayer, &history[1].farLayer, &history[1].moments, &variance});
}

HybridTemporalPass::HybridTemporalPass(const gpu::Context& context, uint32_t width, uint32_t height)
    : context_(context), images_(std::make_unique<Images>(context, width, height)) {
  constexpr VkDescriptorType kSampled = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  pipeline_ = gpu::createComputePipeline(context, "hybrid_temporal.comp", VK_NULL_HANDLE,
                                         {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {kSampled},
                                          {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                          {kStorage},
                                          {kStorage},
                                          {kStorage},
                                          {kStorage}},
                                         sizeof(TemporalPush));
  sampler_ = gpu::createNearestSampler(context);
}

HybridTemporalPass::~HybridTemporalPass() = default;

void HybridTemporalPass::resize(uint32_t width, uint32_t height) {
  if (width == images_->width && height == images_->height) return;
  VK_CHECK(vkQueueWaitIdle(context_.queue()));
  images_.reset();
  images_ = std::make_unique<Images>(context_, width, height);
}

void HybridTemporalPass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                                const gpu::Image& rays, const gpu::Buffer& workList,
                                const HybridTraceLayers& layers, const RenderTargets& targets,
                                bool reset, float minBlend) {
  const History& previous = images_->history[images_->written];
  images_->written ^= 1u;
  const History& next = images_->history[images_->written];
  TemporalPush push{reset ? 1u : 0u, minBlend};
  gpu::clearToZero(cmd, {&next.nearLayer, &next.farLayer, &next.moments, &images_->variance});
  gpu::dispatchComputeIndirect(context_, cmd, pipeline_,
                               gpu::DescriptorWriter()
                                   .uniformBuffer(gpu::kBindingFrame, frameUniforms)
                                   .sampledImage(1, rays, sampler_)
                                   .sampledImage(2, layers.nearLayer, sampler_)
                                   .sampledImage(3, layers.farLayer, sampler_)
                                   .sampledImage(4, layers.farPosition, sampler_)
                                   .sampledImage(5, targets.motion, sampler_)
                                   .sampledImage(6, targets.normalDepth, sampler_)
                                   .sampledImage(7, previous.nearLayer, sampler_)
                                   .sampledImage(8, previous.farLayer, sampler_)
                                   .sampledImage(9, previous.moments, sampler_)
                                   .storageBuffer(10, workList)
                                   .storageImage(11, next.nearLayer)
                                   .storageImage(12, next.farLayer)
                                   .storageImage(13, next.moments)
                                   .storageImage(14, images_->variance),
                               workList, &push);
}

const HybridTemporalPass::History& HybridTemporalPass::current() const {
  return images_->history[images_->written];
}

const gpu::Image& HybridTemporalPass::variance() const { return images_->variance; }

}  // namespace hdof
