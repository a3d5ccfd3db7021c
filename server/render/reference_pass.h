// The thin-lens ray tracer over the whole frame, accumulating progressively: the `reference`
// mode, and the ground truth for quality measurements.
#pragma once

#include "gpu/pipeline.h"
#include "render/render_targets.h"
#include "scene/gpu_scene.h"

namespace hdof {

class ReferencePass {
 public:
  ReferencePass(const gpu::Context& context, const GpuScene& scene);
  // Adds sampleCount rays per pixel (sample numbers firstSample...) to targets.accumulation;
  // firstSample 0 starts over.
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const RenderTargets& targets,
              uint32_t firstSample, uint32_t sampleCount) const;

 private:
  const gpu::Context& context_;
  const GpuScene& scene_;
  gpu::ComputePipeline pipeline_;
};

}  // namespace hdof
