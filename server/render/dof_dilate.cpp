#include "render/dof_dilate.h"

namespace hdof {

DofDilatePass::DofDilatePass(const gpu::Context& context)
    : pass_(context, "dof_dilate.comp", {kDofUniforms, kDofImage, kDofImage}) {}

void DofDilatePass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                           const gpu::Image& tiles, const gpu::Image& dilated) const {
  pass_.dispatch(cmd, frameUniforms, {&tiles, &dilated}, dilated.width(), dilated.height());
}

}  // namespace hdof
