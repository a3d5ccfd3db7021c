#include "render/dof_median.h"

namespace hdof {

DofMedianPass::DofMedianPass(const gpu::Context& context)
    : pass_(context, "dof_median.comp",
            {kDofUniforms, kDofImage, kDofImage, kDofImage, kDofImage, kDofImage}) {}

void DofMedianPass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                           const gpu::Image& farLayer, const gpu::Image& nearLayer,
                           const gpu::Image& dilatedTiles, const gpu::Image& farFiltered,
                           const gpu::Image& nearFiltered) const {
  pass_.dispatch(cmd, frameUniforms,
                 {&farLayer, &nearLayer, &dilatedTiles, &farFiltered, &nearFiltered},
                 farFiltered.width(), farFiltered.height());
}

}  // namespace hdof
