// Debug views of the hybrid (ray mask, hit ratio, CoC, near and far layers), drawn over the
// hybrid's output so that the tonemap shows them.
#pragma once

#include "gpu/pipeline.h"
#include "render/render_targets.h"

#include <optional>
#include <string>

namespace hdof {

enum class DebugView { Final = 0, Mask = 1, HitRatio = 2, Coc = 3, Near = 4, Far = 5 };

const char* debugViewName(DebugView view);
std::optional<DebugView> parseDebugView(const std::string& name);
std::string debugViewNames();  // "final|mask|..."

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
