// Post-process DoF, pass 3: tile dilation. Each tile takes the largest |CoC| and the nearest CoC
// of the neighbouring tiles whose blur reaches it, which sizes its gather kernel.
#pragma once

#include "render/dof_pass.h"

namespace hdof {

class DofDilatePass {
 public:
  explicit DofDilatePass(const gpu::Context& context);
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Image& tiles,
              const gpu::Image& dilated) const;

 private:
  DofComputePass pass_;
};

}  // namespace hdof
