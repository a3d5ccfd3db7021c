// The output pass: HDR radiance to 8-bit sRGB in targets.display, copied to the readback buffer.
#pragma once

#include "gpu/pipeline.h"
#include "render/render_targets.h"

namespace hdof {

class TonemapPass {
 public:
  explicit TonemapPass(const gpu::Context& context);
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Image& radiance,
              const RenderTargets& targets) const;

 private:
  const gpu::Context& context_;
  gpu::ComputePipeline pipeline_;
  gpu::Sampler sampler_;
};

}  // namespace hdof
