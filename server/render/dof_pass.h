// What every pass of the post-process depth of field has in common: a compute shader that reads
// the frame uniforms (binding 0) and storage images (bindings 1, 2, ... in order).
#pragma once

#include "gpu/pipeline.h"

#include <initializer_list>
#include <string>

namespace hdof {

inline constexpr gpu::LayoutBinding kDofUniforms{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER};
inline constexpr gpu::LayoutBinding kDofImage{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};

class DofComputePass {
 public:
  // bindings: kDofUniforms, then one kDofImage per image the shader declares.
  DofComputePass(const gpu::Context& context, const std::string& shaderName,
                 std::initializer_list<gpu::LayoutBinding> bindings);
  // Binds the images (in binding order) and runs one thread per cell of a width x height grid,
  // in square workgroups of groupSize.
  void dispatch(VkCommandBuffer cmd, const gpu::Buffer& frameUniforms,
                std::initializer_list<const gpu::Image*> images, uint32_t width, uint32_t height,
                uint32_t groupSize = 8) const;

 private:
  const gpu::Context& context_;
  std::string name_;
  size_t imageCount_;
  gpu::ComputePipeline pipeline_;
};

}  // namespace hdof
