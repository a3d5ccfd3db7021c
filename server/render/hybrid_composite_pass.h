// Hybrid pass 7, the composite: the accumulated ray-traced layers, the post-process and the sharp
// raster colour joined by each pixel's circle of confusion and hit ratio.
#pragma once

#include "gpu/pipeline.h"
#include "render/hybrid_temporal_pass.h"
#include "render/render_targets.h"

namespace hdof {

class HybridCompositePass {
 public:
  explicit HybridCompositePass(const gpu::Context& context);
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Image& rays,
              const RenderTargets& targets, const gpu::Image& postProcess,
              const HybridTemporalPass::History& history, const gpu::Image& output) const;

 private:
  const gpu::Context& context_;
  gpu::ComputePipeline pipeline_;
  gpu::Sampler sampler_;
};

}  // namespace hdof
