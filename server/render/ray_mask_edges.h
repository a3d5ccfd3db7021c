// Ray mask, pass 1: edges of the filtered G-buffer whose near side is out of focus; per pixel
// (r16f each) the near side's CoC diameter plus a margin (0: no rays needed) and the edge
// strength.
#pragma once

#include "render/dof_pass.h"

namespace hdof {

class RayMaskEdgesPass {
 public:
  explicit RayMaskEdgesPass(const gpu::Context& context);
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Image& normalDepth,
              const gpu::Image& reach, const gpu::Image& strength) const;

 private:
  DofComputePass pass_;
};

}  // namespace hdof
