#include "render/dof_prefilter.h"

namespace hdof {

DofPrefilterPass::DofPrefilterPass(const gpu::Context& context)
    : pass_(context, "dof_prefilter.comp", {kDofUniforms, kDofImage, kDofImage, kDofImage}) {}

void DofPrefilterPass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                              const gpu::Image& halfColorCoc, const gpu::Image& dilatedTiles,
                              const gpu::Image& prefiltered) const {
  pass_.dispatch(cmd, frameUniforms, {&halfColorCoc, &dilatedTiles, &prefiltered},
                 prefiltered.width(), prefiltered.height());
}

}  // namespace hdof
