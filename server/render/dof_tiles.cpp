#include "render/dof_tiles.h"

namespace hdof {

DofTilesPass::DofTilesPass(const gpu::Context& context)
    : pass_(context, "dof_tiles.comp", {kDofUniforms, kDofImage, kDofImage}) {}

void DofTilesPass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                          const gpu::Image& coc, const gpu::Image& tiles) const {
  pass_.dispatch(cmd, frameUniforms, {&coc, &tiles}, tiles.width(), tiles.height());
}

}  // namespace hdof
