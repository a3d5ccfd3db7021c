// Debug views of the hybrid (ray mask, hit ratio, CoC, near and far layers), drawn over the
// hybrid's output so that the tonemap shows them.
#pragma once

#include "gpu/pipeline.h"
#include "render/modes.h"
#include "render/render_targets.h"

#include <optional>
#include <string>

namespace hdof {

class DebugViewPass {
 public:
  explicit DebugViewPass(const gpu::Context& context);
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, DebugView view,
              const gpu::Image& rays, const RenderTargets& targets, const gpu::Image& nearLayer,
              const gpu::Image& farLayer, const gpu::Image& output) const;

 private:
  const gpu::Context& context_;
  gpu::ComputePipeline pipeline_;
  gpu::Sampler sampler_;
};

}  // namespace hdof
