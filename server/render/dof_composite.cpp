#include "render/dof_composite.h"

namespace hdof {

DofCompositePass::DofCompositePass(const gpu::Context& context)
    : pass_(context, "dof_composite.comp",
            {kDofUniforms, kDofImage, kDofImage, kDofImage, kDofImage, kDofImage, kDofImage}) {}

void DofCompositePass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                              const gpu::Image& color, const gpu::Image& coc,
                              const gpu::Image& farLayer, const gpu::Image& nearLayer,
                              const gpu::Image& dilatedTiles, const gpu::Image& result) const {
  // One thread per 2x2 pixels: one per half-resolution pixel.
  pass_.dispatch(cmd, frameUniforms, {&color, &coc, &farLayer, &nearLayer, &dilatedTiles, &result},
                 farLayer.width(), farLayer.height());
}

}  // namespace hdof
