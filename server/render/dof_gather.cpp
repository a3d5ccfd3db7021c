#include "render/dof_gather.h"

namespace hdof {

DofGatherPass::DofGatherPass(const gpu::Context& context)
    : pass_(context, "dof_gather.comp",
            {kDofUniforms, kDofImage, kDofImage, kDofImage, kDofImage}) {}

void DofGatherPass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                           const gpu::Image& prefiltered, const gpu::Image& dilatedTiles,
                           const gpu::Image& farLayer, const gpu::Image& nearLayer) const {
  // 8x8 half-resolution pixels are one tile: the kernel size is uniform across a workgroup.
  pass_.dispatch(cmd, frameUniforms, {&prefiltered, &dilatedTiles, &farLayer, &nearLayer},
                 farLayer.width(), farLayer.height(), 8);
}

}  // namespace hdof
