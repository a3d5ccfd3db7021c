// The thin-lens ray tracer over the whole frame, accumulating progressively: the `reference`
// mode (the ground truth for quality measurements) and the `raytrace` mode.
#pragma once

#include "gpu/pipeline.h"
#include "render/render_targets.h"
#include "scene/gpu_scene.h"

namespace hdof {

class ReferencePass {
 public:
  ReferencePass(const gpu::Context& context, const GpuScene& scene);
  struct Rays {
    uint32_t firstSample;  // number of the first ray in each pixel's sample sequence
    uint32_t count;        // rays per pixel to trace
    bool accumulate;       // add to targets.accumulation, or start it over
    uint32_t sequence;  // which family of sample sequences: 0 for the reference, others for modes
  };
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const RenderTargets& targets,
              const Rays& rays) const;

 private:
  const gpu::Context& context_;
  const GpuScene& scene_;
  gpu::ComputePipeline pipeline_;
};

}  // namespace hdof
