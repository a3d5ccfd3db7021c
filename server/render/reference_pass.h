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
  // Traces sampleCount rays per pixel (numbers firstSample... of each pixel's sample sequence)
  // and adds them to targets.accumulation, or starts it over when accumulate is false.
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const RenderTargets& targets,
              uint32_t firstSample, uint32_t sampleCount, bool accumulate) const;

 private:
  const gpu::Context& context_;
  const GpuScene& scene_;
  gpu::ComputePipeline pipeline_;
};

}  // namespace hdof
