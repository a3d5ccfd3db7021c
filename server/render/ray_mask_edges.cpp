#include "render/ray_mask_edges.h"

namespace hdof {

RayMaskEdgesPass::RayMaskEdgesPass(const gpu::Context& context)
    : pass_(context, "ray_mask_edges.comp", {kDofUniforms, kDofImage, kDofImage, kDofImage}) {}

void RayMaskEdgesPass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                              const gpu::Image& normalDepth, const gpu::Image& reach,
                              const gpu::Image& strength) const {
  pass_.dispatch(cmd, frameUniforms, {&normalDepth, &reach, &strength}, reach.width(),
                 reach.height());
}

}  // namespace hdof
