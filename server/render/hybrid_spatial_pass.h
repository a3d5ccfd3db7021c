// Hybrid pass 6, spatial reconstruction: each traced pixel's accumulated layers denoised by a
// CoC-sized circular gather over its traced neighbours, weighted by the noise left in its
// average. Owns the reconstructed layers (only the listed pixels are written).
#pragma once

#include "gpu/pipeline.h"
#include "render/hybrid_temporal_pass.h"
#include "render/hybrid_trace_pass.h"

#include <memory>

namespace hdof {

class HybridSpatialPass {
 public:
  HybridSpatialPass(const gpu::Context& context, uint32_t width, uint32_t height);
  ~HybridSpatialPass();
  HybridSpatialPass(const HybridSpatialPass&) = delete;
  HybridSpatialPass& operator=(const HybridSpatialPass&) = delete;

  void resize(uint32_t width, uint32_t height);
  // workList and rays: the ray mask's, this frame; layers: the trace's (for the layer CoCs);
  // temporal: after this frame's record().
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Buffer& workList,
              const gpu::Image& rays, const HybridTraceLayers& layers,
              const HybridTemporalPass& temporal) const;

  // rgba16f, as HybridTemporalPass::History's: near colour x hit ratio and the ratio; far colour
  // x (1 - ratio).
  const gpu::Image& nearLayer() const { return *near_; }
  const gpu::Image& farLayer() const { return *far_; }

 private:
  const gpu::Context& context_;
  gpu::ComputePipeline pipeline_;
  gpu::Sampler sampler_;
  std::unique_ptr<gpu::Image> near_, far_;
};

}  // namespace hdof
