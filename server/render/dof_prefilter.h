// Post-process DoF, pass 4: a small disc filter at half resolution, about as wide as the gap
// between the gather's taps, so sparse taps do not miss small bright highlights.
#pragma once

#include "render/dof_pass.h"

namespace hdof {

class DofPrefilterPass {
 public:
  explicit DofPrefilterPass(const gpu::Context& context);
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Image& halfColorCoc,
              const gpu::Image& dilatedTiles, const gpu::Image& prefiltered) const;

 private:
  DofComputePass pass_;
};

}  // namespace hdof
