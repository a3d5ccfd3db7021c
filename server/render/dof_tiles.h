// Post-process DoF, pass 2: per tile of kDofTileSize pixels (rg16f, one texel per tile), the
// largest |CoC| and the nearest (most negative) CoC.
#pragma once

#include "render/dof_pass.h"

namespace hdof {

class DofTilesPass {
 public:
  explicit DofTilesPass(const gpu::Context& context);
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Image& coc,
              const gpu::Image& tiles) const;

 private:
  DofComputePass pass_;
};

}  // namespace hdof
