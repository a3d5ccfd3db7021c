// Hybrid pass 7, the composite: the reconstructed ray-traced layers (nearLayer: colour x hit
// ratio and the ratio; farLayer: colour x (1 - ratio)), the post-process and the sharp raster
// colour joined by each pixel's circle of confusion and hit ratio.
#pragma once

#include "gpu/pipeline.h"
#include "render/render_targets.h"

namespace hdof {

class HybridCompositePass {
 public:
  explicit HybridCompositePass(const gpu::Context& context);
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Image& rays,
              const RenderTargets& targets, const gpu::Image& postProcess,
              const gpu::Image& nearLayer, const gpu::Image& farLayer,
              const gpu::Image& output) const;

 private:
  const gpu::Context& context_;
  gpu::ComputePipeline pipeline_;
  gpu::Sampler sampler_;
};

}  // namespace hdof
