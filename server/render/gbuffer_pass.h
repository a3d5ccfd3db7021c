// Pass 1, the G-buffer: the scene rasterised and shaded with the shared shading function into
// colour, specular and normal/depth targets.
#pragma once

#include "gpu/pipeline.h"
#include "render/render_targets.h"
#include "scene/gpu_scene.h"

namespace hdof {

class GBufferPass {
 public:
  GBufferPass(const gpu::Context& context, const GpuScene& scene);

  // Makes the framebuffer for a new set of targets (call after they change).
  void bindTargets(const RenderTargets& targets);
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
              const RenderTargets& targets) const;

 private:
  const gpu::Context& context_;
  const GpuScene& scene_;
  gpu::RenderPass renderPass_;
  gpu::Framebuffer framebuffer_;
  gpu::DescriptorSetLayout passSetLayout_;
  gpu::PipelineLayout layout_;
  gpu::Pipeline pipeline_;
};

}  // namespace hdof
