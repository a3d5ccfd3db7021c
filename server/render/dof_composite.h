// Post-process DoF, pass 7: full resolution: the sharp colour in the focus zone, the far layer
// blended in by |CoC| beyond it, the near layer over everything.
#pragma once

#include "render/dof_pass.h"

namespace hdof {

class DofCompositePass {
 public:
  explicit DofCompositePass(const gpu::Context& context);
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Image& color,
              const gpu::Image& coc, const gpu::Image& farLayer, const gpu::Image& nearLayer,
              const gpu::Image& dilatedTiles, const gpu::Image& result) const;

 private:
  DofComputePass pass_;
};

}  // namespace hdof
