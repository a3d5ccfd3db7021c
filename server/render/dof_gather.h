// Post-process DoF, pass 5: the half-resolution scatter-as-gather into a far layer (normalised,
// alpha = CoC) and a near layer (premultiplied, alpha = opacity). See shaders/dof_gather.comp.
#pragma once

#include "render/dof_pass.h"

namespace hdof {

class DofGatherPass {
 public:
  explicit DofGatherPass(const gpu::Context& context);
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Image& prefiltered,
              const gpu::Image& dilatedTiles, const gpu::Image& farLayer,
              const gpu::Image& nearLayer) const;

 private:
  DofComputePass pass_;
};

}  // namespace hdof
