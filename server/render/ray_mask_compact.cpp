#include "render/ray_mask_compact.h"

#include "render/dof_pass.h"

#include <shared/frame.h>

namespace hdof {

namespace {
constexpr gpu::LayoutBinding kWorkList{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
}

RayMaskCompactPass::RayMaskCompactPass(const gpu::Context& context)
    : context_(context),
      compact_(gpu::createComputePipeline(context, "ray_mask_compact.comp", VK_NULL_HANDLE,
                                          {kDofUniforms, kWorkList, kDofImage})),
      indirect_(gpu::createComputePipeline(context, "ray_mask_indirect.comp", VK_NULL_HANDLE,
                                           {kDofUniforms, kWorkList})) {}

void RayMaskCompactPass::record(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                                const gpu::Image& rays, const gpu::Buffer& workList) const {
  gpu::DescriptorWriter compactWriter;
  compactWriter.uniformBuffer(gpu::kBindingFrame, frameUniforms)
      .storageBuffer(1, workList)
      .storageImage(2, rays);
  gpu::dispatchCompute(context_, cmd, compact_, compactWriter, rays.width(), rays.height());
  // The count is final only once every workgroup has appended.
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  gpu::DescriptorWriter indirectWriter;
  indirectWriter.uniformBuffer(gpu::kBindingFrame, frameUniforms).storageBuffer(1, workList);
  gpu::dispatchCompute(context_, cmd, indirect_, indirectWriter, 1, 1, 1);
}

}  // namespace hdof
