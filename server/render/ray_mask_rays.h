// Ray mask, pass 5: the column half of the disc dilation, and the rays per pixel (r8ui) from the
// edges and the luminance variance of the ray-traced output.
#pragma once

#include "gpu/pipeline.h"

namespace hdof {

class RayMaskRaysPass {
 public:
  explicit RayMaskRaysPass(const gpu::Context& context);
  // variance: any single-channel float image, read through a nearest sampler. everywhere: every
  // pixel gets the full rays (to measure the reconstruction without the mask).
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Image& spread,
              const gpu::Image& dilatedTiles, const gpu::Image& variance, const gpu::Image& rays,
              bool everywhere = false) const;

 private:
  const gpu::Context& context_;
  gpu::ComputePipeline pipeline_;
  gpu::Sampler sampler_;
};

}  // namespace hdof
