// Post-process DoF, pass 6: a 3x3 median of both half-resolution layers, against the noise of
// a sparse gather.
#pragma once

#include "render/dof_pass.h"

namespace hdof {

class DofMedianPass {
 public:
  explicit DofMedianPass(const gpu::Context& context);
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Image& farLayer,
              const gpu::Image& nearLayer, const gpu::Image& dilatedTiles,
              const gpu::Image& farFiltered, const gpu::Image& nearFiltered) const;

 private:
  DofComputePass pass_;
};

}  // namespace hdof
