// Pass 1, the G-buffer, in two stages: a raster visibility pass writes the triangle seen at each
// pixel centre, then a compute resolve shades that point once per pixel with the shading code the
// ray tracer uses, into colour, specular and normal/depth targets.
#pragma once

#include "gpu/pipeline.h"
#include "render/raster_culling.h"
#include "render/render_targets.h"
#include "scene/gpu_scene.h"

namespace hdof {

class GBufferPass {
 public:
  GBufferPass(const gpu::Context& context, const Scene& scene, const GpuScene& gpuScene);

  // Makes the framebuffer for a new set of targets (call after they change).
  void bindTargets(const RenderTargets& targets);
  // The raster visibility stage, then the compute resolve (timed separately by the caller).
  void recordVisibility(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                        const RenderTargets& targets) const;
  void recordResolve(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                     const RenderTargets& targets) const;

 private:
  const gpu::Context& context_;
  const GpuScene& scene_;
  std::vector<TriangleRun> runs_;
  gpu::RenderPass renderPass_;
  gpu::Framebuffer framebuffer_;
  gpu::DescriptorSetLayout passSetLayout_;
  gpu::PipelineLayout layout_;
  gpu::Pipeline pipeline_;
  gpu::ComputePipeline resolve_;
};

}  // namespace hdof
