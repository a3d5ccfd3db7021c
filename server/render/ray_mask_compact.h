// Ray mask, pass 6: appends every pixel with rays to the work list (shared/ray_work.h), then
// writes the list's indirect dispatch arguments. The list's count must be zero before.
#pragma once

#include "gpu/pipeline.h"

namespace hdof {

class RayMaskCompactPass {
 public:
  explicit RayMaskCompactPass(const gpu::Context& context);
  void record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms, const gpu::Image& rays,
              const gpu::Buffer& workList) const;

 private:
  const gpu::Context& context_;
  gpu::ComputePipeline compact_, indirect_;
};

}  // namespace hdof
