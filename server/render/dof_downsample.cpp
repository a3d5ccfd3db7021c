#include "render/dof_downsample.h"

namespace hdof {

DofDownsamplePass::DofDownsamplePass(const gpu::Context& context)
    : pass_(context, "dof_downsample.comp",
            {kDofUniforms, kDofImage, kDofImage, kDofImage, kDofImage}) {}

void DofDownsamplePass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                               const gpu::Image& color, const gpu::Image& normalDepth,
                               const gpu::Image& coc, const gpu::Image& halfColorCoc) const {
  // One thread per half-resolution pixel, which also writes the CoC of its 2x2 pixels.
  pass_.dispatch(cmd, frameUniforms, {&color, &normalDepth, &coc, &halfColorCoc},
                 halfColorCoc.width(), halfColorCoc.height());
}

}  // namespace hdof
