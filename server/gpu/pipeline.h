// Pipelines from the SPIR-V embedded at build time, descriptor set layouts, and push descriptors
// (each pass pushes its per-frame bindings into set 1; set 0 is the shared scene).
#pragma once

#include "gpu/resources.h"

#include <deque>
#include <initializer_list>
#include <string>
#include <vector>

namespace hdof {
std::span<const uint32_t> embeddedShader(const std::string& name);  // generated at build time
std::vector<std::string> embeddedShaderNames();                     // every one, sorted
}

namespace hdof::gpu {

// The stages every descriptor and push-constant range of hdof is visible to.
inline constexpr VkShaderStageFlags kAllShaderStages =
    VK_SHADER_STAGE_COMPUTE_BIT | VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;

ShaderModule createShaderModule(const Context& context, const std::string& name);

struct LayoutBinding {
  VkDescriptorType type;
  uint32_t count = 1;
};

// Bindings numbered 0, 1, ... in the order given, visible to all stages used by hdof.
DescriptorSetLayout createSetLayout(const Context& context,
                                    std::initializer_list<LayoutBinding> bindings,
                                    bool pushDescriptors, const std::string& name);

PipelineLayout createPipelineLayout(const Context& context,
                                    std::initializer_list<VkDescriptorSetLayout> setLayouts,
                                    uint32_t pushConstantSize);

struct ComputePipeline {
  DescriptorSetLayout passSetLayout;  // set 1, pushed per dispatch
  PipelineLayout layout;
  Pipeline pipeline;
  uint32_t pushConstantSize = 0;
};

// A compute pipeline for shaders/NAME.comp with set 0 = sceneSetLayout (may be null when the
// shader does not touch the scene) and set 1 = passBindings.
ComputePipeline createComputePipeline(const Context& context, const std::string& shaderName,
                                      VkDescriptorSetLayout sceneSetLayout,
                                      std::initializer_list<LayoutBinding> passBindings,
                                      uint32_t pushConstantSize = 0);

// Collects descriptor writes for one push (the infos stay alive until push()).
class DescriptorWriter {
 public:
  DescriptorWriter& uniformBuffer(uint32_t binding, const Buffer& buffer);
  DescriptorWriter& storageBuffer(uint32_t binding, const Buffer& buffer);
  DescriptorWriter& storageImage(uint32_t binding, const Image& image);
  // A render target read through a sampler; render targets stay in VK_IMAGE_LAYOUT_GENERAL.
  DescriptorWriter& sampledImage(uint32_t binding, const Image& image, VkSampler sampler);
  void push(const Context& context, VkCommandBuffer cmd, VkPipelineBindPoint bindPoint,
            VkPipelineLayout layout, uint32_t set) const;

 private:
  VkWriteDescriptorSet& add(uint32_t binding, VkDescriptorType type);
  std::deque<VkDescriptorBufferInfo> buffers_;
  std::deque<VkDescriptorImageInfo> images_;
  std::vector<VkWriteDescriptorSet> writes_;
};

// Binds a compute pipeline, pushes its pass descriptors and dispatches enough workgroups of
// groupSize x groupSize threads to cover width x height.
void dispatchCompute(const Context& context, VkCommandBuffer cmd, const ComputePipeline& pipeline,
                     const DescriptorWriter& passDescriptors, uint32_t width, uint32_t height,
                     uint32_t groupSize = 8, const void* pushConstants = nullptr);

// The same, with the workgroup counts read from a VkDispatchIndirectCommand at the start of
// indirectArgs (a buffer with VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT).
void dispatchComputeIndirect(const Context& context, VkCommandBuffer cmd,
                             const ComputePipeline& pipeline,
                             const DescriptorWriter& passDescriptors, const Buffer& indirectArgs,
                             const void* pushConstants = nullptr);

}  // namespace hdof::gpu
