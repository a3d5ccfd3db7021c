// Hybrid pass 5, temporal accumulation: the selective ray trace's near and far layers averaged
// over frames with reprojection (near by motion vectors, far through the far world position),
// history rejected on disocclusion and cuts, and the luminance variance for the next ray mask.
// Owns the history, as two sets of images that swap roles each frame.
#pragma once

#include "gpu/pipeline.h"
#include "render/hybrid_trace_pass.h"
#include "render/render_targets.h"

#include <array>
#include <memory>

namespace hdof {

class HybridTemporalPass {
 public:
  HybridTemporalPass(const gpu::Context& context, uint32_t width, uint32_t height);
  ~HybridTemporalPass();
  HybridTemporalPass(const HybridTemporalPass&) = delete;
  HybridTemporalPass& operator=(const HybridTemporalPass&) = delete;

  void resize(uint32_t width, uint32_t height);
  // rays: the ray mask's rays per pixel this frame (r8ui, sampled); workList: its pixels (one
  // thread each; the other pixels' history is cleared). reset: a cut (or the first frame): start
  // every pixel's history over. minBlend: the new frame's weight once history is
  // long (the moving average's floor; lower is smoother in stills, slower to follow motion).
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Image& rays,
              const gpu::Buffer& workList, const HybridTraceLayers& layers,
              const RenderTargets& targets, bool reset, float minBlend = 0.1f);

  struct History {
    gpu::Image nearLayer;  // rgba16f: accumulated near colour, accumulated hit ratio
    gpu::Image farLayer;   // rgba16f: accumulated far colour, rays accumulated
    gpu::Image moments;    // rgba32f: luminance mean, mean square, rays accumulated, depth
  };
  // What the last record() wrote.
  const History& current() const;
  // r16f: luminance variance of one ray of the ray-traced colour (high where history is short;
  // 0 where the mask did not trace).
  const gpu::Image& variance() const;

 private:
  struct Images;
  const gpu::Context& context_;
  std::unique_ptr<Images> images_;
  gpu::ComputePipeline pipeline_;
  gpu::Sampler sampler_;
};

}  // namespace hdof
