// Post-process DoF, pass 1: the signed CoC of every pixel (r16f, full resolution), and colour and
// CoC at half resolution (rgba16f, alpha = CoC): the nearest CoC of each 2x2 block, colours
// weighted by CoC similarity to it.
#pragma once

#include "render/dof_pass.h"

namespace hdof {

class DofDownsamplePass {
 public:
  explicit DofDownsamplePass(const gpu::Context& context);
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Image& color,
              const gpu::Image& normalDepth, const gpu::Image& coc,
              const gpu::Image& halfColorCoc) const;

 private:
  DofComputePass pass_;
};

}  // namespace hdof
