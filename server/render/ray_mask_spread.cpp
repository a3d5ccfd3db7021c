#include "render/ray_mask_spread.h"

namespace hdof {

RayMaskSpreadPass::RayMaskSpreadPass(const gpu::Context& context)
    : pass_(context, "ray_mask_spread.comp",
            {kDofUniforms, kDofImage, kDofImage, kDofImage, kDofImage}) {}

void RayMaskSpreadPass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                               const gpu::Image& reach, const gpu::Image& strength,
                               const gpu::Image& dilatedTiles, const gpu::Image& spread) const {
  pass_.dispatch(cmd, frameUniforms, {&reach, &strength, &dilatedTiles, &spread}, spread.width(),
                 spread.height());
}

}  // namespace hdof
