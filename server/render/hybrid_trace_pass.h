// Hybrid pass 4, the selective ray trace: thin-lens rays for the pixels of the ray mask's work
// list only (an indirect dispatch over the list, so the work scales with the mask's coverage),
// split into near and far layers for the reconstruction.
#pragma once

#include "gpu/pipeline.h"
#include "scene/gpu_scene.h"

namespace hdof {

// What the selective ray trace writes, full resolution; only listed pixels are written.
struct HybridTraceLayers {
  HybridTraceLayers(const gpu::Context& context, uint32_t width, uint32_t height);
  gpu::Image nearLayer;    // rgba16f: average near-layer colour, alpha the hit ratio
  gpu::Image farLayer;     // rgba16f: average far-layer colour, alpha 1 - hit ratio
  gpu::Image farPosition;  // rgba32f: average world position of far hits, w their weight
  gpu::Image layerCoc;     // rg16f: average near |CoC| and far CoC, pixels
  // r32ui, kept from frame to frame: how many rays each pixel has traced so far, so that its
  // next rays continue its sample sequence whatever the mask gave it in earlier frames.
  gpu::Image samplesTraced;
};

class HybridTracePass {
 public:
  HybridTracePass(const gpu::Context& context, const GpuScene& scene);
  // workList: a buffer laid out as in shared/ray_work.h, already filled on the GPU.
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Buffer& workList,
              const HybridTraceLayers& layers) const;

 private:
  const gpu::Context& context_;
  const GpuScene& scene_;
  gpu::ComputePipeline pipeline_;
};

}  // namespace hdof
