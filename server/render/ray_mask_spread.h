// Ray mask, pass 4: the row half of the separable disc dilation of the edges (rg16f: the half
// height of the widest edge disc over each pixel, -1 for none; the strongest such edge).
#pragma once

#include "render/dof_pass.h"

namespace hdof {

class RayMaskSpreadPass {
 public:
  explicit RayMaskSpreadPass(const gpu::Context& context);
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Image& reach,
              const gpu::Image& strength, const gpu::Image& dilatedTiles,
              const gpu::Image& spread) const;

 private:
  DofComputePass pass_;
};

}  // namespace hdof
