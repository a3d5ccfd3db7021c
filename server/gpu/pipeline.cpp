#include "gpu/pipeline.h"

#include <shared/frame.h>
#include <shared/scene_data.h>

namespace hdof::gpu {

ShaderModule createShaderModule(const Context& context, const std::string& name) {
  std::span<const uint32_t> code = embeddedShader(name);
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = code.size_bytes();
  info.pCode = code.data();
  VkShaderModule module = VK_NULL_HANDLE;
  VK_CHECK(vkCreateShaderModule(context.device(), &info, nullptr, &module));
  context.setName(VK_OBJECT_TYPE_SHADER_MODULE, reinterpret_cast<uint64_t>(module), name);
  return ShaderModule(context.device(), module);
}

DescriptorSetLayout createSetLayout(const Context& context,
                                    std::initializer_list<LayoutBinding> bindings,
                                    bool pushDescriptors, const std::string& name) {
  std::vector<VkDescriptorSetLayoutBinding> vkBindings;
  for (const LayoutBinding& b : bindings)
    vkBindings.push_back(
        {static_cast<uint32_t>(vkBindings.size()), b.type, b.count, kAllShaderStages, nullptr});
  VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  if (pushDescriptors) info.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
  info.bindingCount = static_cast<uint32_t>(vkBindings.size());
  info.pBindings = vkBindings.data();
  VkDescriptorSetLayout layout = VK_NULL_HANDLE;
  VK_CHECK(vkCreateDescriptorSetLayout(context.device(), &info, nullptr, &layout));
  context.setName(VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, reinterpret_cast<uint64_t>(layout), name);
  return DescriptorSetLayout(context.device(), layout);
}

PipelineLayout createPipelineLayout(const Context& context,
                                    std::initializer_list<VkDescriptorSetLayout> setLayouts,
                                    uint32_t pushConstantSize) {
  std::vector<VkDescriptorSetLayout> layouts(setLayouts);
  VkPushConstantRange range{kAllShaderStages, 0, pushConstantSize};
  VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  info.setLayoutCount = static_cast<uint32_t>(layouts.size());
  info.pSetLayouts = layouts.data();
  info.pushConstantRangeCount = pushConstantSize ? 1 : 0;
  info.pPushConstantRanges = &range;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VK_CHECK(vkCreatePipelineLayout(context.device(), &info, nullptr, &layout));
  return PipelineLayout(context.device(), layout);
}

ComputePipeline createComputePipeline(const Context& context, const std::string& shaderName,
                                      VkDescriptorSetLayout sceneSetLayout,
                                      std::initializer_list<LayoutBinding> passBindings,
                                      uint32_t pushConstantSize) {
  ComputePipeline result;
  result.pushConstantSize = pushConstantSize;
  result.passSetLayout = createSetLayout(context, passBindings, true, shaderName + " pass set");
  // Set 0 must exist in the layout even for passes that do not read the scene; an empty
  // layout keeps the set numbers the same in every shader.
  DescriptorSetLayout emptySceneLayout;
  if (!sceneSetLayout) {
    emptySceneLayout = createSetLayout(context, {}, false, "empty scene set");
    sceneSetLayout = emptySceneLayout;
  }
  result.layout =
      createPipelineLayout(context, {sceneSetLayout, result.passSetLayout}, pushConstantSize);
  ShaderModule module = createShaderModule(context, shaderName);
  VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module;
  info.stage.pName = "main";
  info.layout = result.layout;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VK_CHECK(
      vkCreateComputePipelines(context.device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
  context.setName(VK_OBJECT_TYPE_PIPELINE, reinterpret_cast<uint64_t>(pipeline), shaderName);
  result.pipeline = Pipeline(context.device(), pipeline);
  return result;
}

VkWriteDescriptorSet& DescriptorWriter::add(uint32_t binding, VkDescriptorType type) {
  VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  write.dstBinding = binding;
  write.descriptorCount = 1;
  write.descriptorType = type;
  return writes_.emplace_back(write);
}

DescriptorWriter& DescriptorWriter::uniformBuffer(uint32_t binding, const Buffer& buffer) {
  add(binding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER).pBufferInfo =
      &buffers_.emplace_back(buffer.descriptor());
  return *this;
}

DescriptorWriter& DescriptorWriter::storageBuffer(uint32_t binding, const Buffer& buffer) {
  add(binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER).pBufferInfo =
      &buffers_.emplace_back(buffer.descriptor());
  return *this;
}

DescriptorWriter& DescriptorWriter::storageImage(uint32_t binding, const Image& image) {
  add(binding, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE).pImageInfo = &images_.emplace_back(
      VkDescriptorImageInfo{VK_NULL_HANDLE, image.view(), VK_IMAGE_LAYOUT_GENERAL});
  return *this;
}

DescriptorWriter& DescriptorWriter::sampledImage(uint32_t binding, const Image& image,
                                                 VkSampler sampler) {
  add(binding, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER).pImageInfo =
      &images_.emplace_back(VkDescriptorImageInfo{sampler, image.view(), VK_IMAGE_LAYOUT_GENERAL});
  return *this;
}

void DescriptorWriter::push(const Context& context, VkCommandBuffer cmd,
                            VkPipelineBindPoint bindPoint, VkPipelineLayout layout,
                            uint32_t set) const {
  context.cmdPushDescriptorSet(cmd, bindPoint, layout, set, static_cast<uint32_t>(writes_.size()),
                               writes_.data());
}

namespace {

void bindCompute(const Context& context, VkCommandBuffer cmd, const ComputePipeline& pipeline,
                 const DescriptorWriter& passDescriptors, const void* pushConstants) {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.pipeline);
  passDescriptors.push(context, cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.layout, kPassSet);
  if (pipeline.pushConstantSize)
    vkCmdPushConstants(cmd, pipeline.layout, kAllShaderStages, 0, pipeline.pushConstantSize,
                       pushConstants);
}

}  // namespace

void dispatchCompute(const Context& context, VkCommandBuffer cmd, const ComputePipeline& pipeline,
                     const DescriptorWriter& passDescriptors, uint32_t width, uint32_t height,
                     uint32_t groupSize, const void* pushConstants) {
  bindCompute(context, cmd, pipeline, passDescriptors, pushConstants);
  vkCmdDispatch(cmd, (width + groupSize - 1) / groupSize, (height + groupSize - 1) / groupSize, 1);
}

void dispatchComputeIndirect(const Context& context, VkCommandBuffer cmd,
                             const ComputePipeline& pipeline,
                             const DescriptorWriter& passDescriptors, const Buffer& indirectArgs,
                             const void* pushConstants) {
  bindCompute(context, cmd, pipeline, passDescriptors, pushConstants);
  vkCmdDispatchIndirect(cmd, indirectArgs.get(), 0);
}

}  // namespace hdof::gpu
