#include "gpu/program.h"

#include <shared/frame.h>
#include <shared/scene_data.h>

#include <algorithm>
#include <deque>
#include <stdexcept>

namespace hdof::gpu {
namespace {

bool isImage(VkDescriptorType type) {
  return type == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE ||
         type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER ||
         type == VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
}

bool isBuffer(VkDescriptorType type) {
  return type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER || type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
}

std::string stem(const std::string& shaderName) {
  return shaderName.substr(0, shaderName.find('.'));
}

std::string namesOf(const std::vector<ShaderBinding>& bindings) {
  std::string names;
  for (const ShaderBinding& b : bindings) names += (names.empty() ? "" : ", ") + b.name;
  return names;
}

// The bindings of set `set` over all stages; a binding two stages share must agree.
std::vector<ShaderBinding> bindingsOfSet(const std::string& name,
                                         std::span<const ShaderInterface> stages, uint32_t set) {
  std::vector<ShaderBinding> merged;
  for (const ShaderInterface& stage : stages)
    for (const ShaderBinding& b : stage.bindingsOf(set)) {
      auto same = std::find_if(merged.begin(), merged.end(),
                               [&](const ShaderBinding& m) { return m.binding == b.binding; });
      if (same == merged.end())
        merged.push_back(b);
      else if (same->type != b.type || same->name != b.name)
        throw std::logic_error(name + ": stages disagree on set " + std::to_string(set) +
                               " binding " + std::to_string(b.binding));
    }
  std::sort(merged.begin(), merged.end(),
            [](const ShaderBinding& a, const ShaderBinding& b) { return a.binding < b.binding; });
  return merged;
}

// The scene's bindings a shader declares must be the scene set's, with the same types.
void checkSceneBindings(const std::string& name, const std::vector<ShaderBinding>& declared,
                        const SetLayout& sceneSet) {
  for (const ShaderBinding& b : declared) {
    auto match =
        std::find_if(sceneSet.bindings.begin(), sceneSet.bindings.end(),
                     [&](const VkDescriptorSetLayoutBinding& s) { return s.binding == b.binding; });
    if (match == sceneSet.bindings.end() || match->descriptorType != b.type ||
        match->descriptorCount != b.count)
      throw std::logic_error(name + ": scene binding '" + b.name + "' (" +
                             std::to_string(b.binding) + ") does not match the scene's set");
  }
}

}  // namespace

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

SetLayout createSetLayout(const Context& context,
                          std::vector<VkDescriptorSetLayoutBinding> bindings, bool pushDescriptors,
                          const std::string& name) {
  VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  if (pushDescriptors) info.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
  info.bindingCount = static_cast<uint32_t>(bindings.size());
  info.pBindings = bindings.data();
  VkDescriptorSetLayout layout = VK_NULL_HANDLE;
  VK_CHECK(vkCreateDescriptorSetLayout(context.device(), &info, nullptr, &layout));
  context.setName(VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, reinterpret_cast<uint64_t>(layout), name);
  return {DescriptorSetLayout(context.device(), layout), std::move(bindings)};
}

std::string SetLayout::key() const {
  std::string key;
  for (const VkDescriptorSetLayoutBinding& b : bindings)
    key += std::to_string(b.binding) + ':' + std::to_string(b.descriptorType) + 'x' +
           std::to_string(b.descriptorCount) + ',';
  return key;
}

ProgramLayout::ProgramLayout(const Context& context, const std::string& name,
                             std::span<const ShaderInterface> stages, const SetLayout* sceneSet)
    : context_(&context), name_(name), passBindings_(bindingsOfSet(name, stages, kPassSet)) {
  for (const ShaderInterface& stage : stages) {
    for (const ShaderBinding& b : stage.bindings)
      if (b.set != kSceneSet && b.set != kPassSet)
        throw std::logic_error(name + ": '" + b.name + "' is in set " + std::to_string(b.set) +
                               "; shaders use set 0 (scene) and 1 (pass)");
    pushConstantSize_ = std::max(pushConstantSize_, stage.pushConstantSize);
  }
  std::vector<ShaderBinding> sceneBindings = bindingsOfSet(name, stages, kSceneSet);
  readsScene_ = !sceneBindings.empty();
  if (readsScene_ && !sceneSet)
    throw std::logic_error(name + " reads the scene (set 0) but was given no scene");
  if (readsScene_) checkSceneBindings(name, sceneBindings, *sceneSet);

  std::vector<VkDescriptorSetLayoutBinding> pass;
  for (const ShaderBinding& b : passBindings_)
    pass.push_back({b.binding, b.type, b.count, kAllShaderStages, nullptr});
  passSet_ = createSetLayout(context, std::move(pass), true, name + " pass set");
  // Set 0 exists in every layout, empty for shaders that do not read the scene, so that set
  // numbers are the same in every shader.
  if (!readsScene_) emptySet_ = createSetLayout(context, {}, false, name + " no scene");
  VkDescriptorSetLayout sets[] = {readsScene_ ? sceneSet->handle.get() : emptySet_.handle.get(),
                                  passSet_.handle};
  VkPushConstantRange range{kAllShaderStages, 0, pushConstantSize_};
  VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  info.setLayoutCount = 2;
  info.pSetLayouts = sets;
  info.pushConstantRangeCount = pushConstantSize_ ? 1 : 0;
  info.pPushConstantRanges = &range;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VK_CHECK(vkCreatePipelineLayout(context.device(), &info, nullptr, &layout));
  layout_ = PipelineLayout(context.device(), layout);
}

void ProgramLayout::bind(VkCommandBuffer cmd, VkPipelineBindPoint bindPoint,
                         std::span<const Bind> binds, PushConstants push) const {
  if (push.size != pushConstantSize_)
    throw std::logic_error(name_ + ": " + std::to_string(push.size) +
                           " bytes of push constants given, the shader declares " +
                           std::to_string(pushConstantSize_));
  std::deque<VkDescriptorBufferInfo> buffers;
  std::deque<VkDescriptorImageInfo> images;
  std::vector<VkWriteDescriptorSet> writes;
  for (const ShaderBinding& b : passBindings_) {
    auto given = std::find_if(binds.begin(), binds.end(),
                              [&](const Bind& bind) { return b.name == bind.name; });
    if (given == binds.end()) throw std::logic_error(name_ + ": nothing bound to '" + b.name + "'");
    if (std::find_if(given + 1, binds.end(),
                     [&](const Bind& bind) { return b.name == bind.name; }) != binds.end())
      throw std::logic_error(name_ + ": '" + b.name + "' bound twice");
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstBinding = b.binding;
    write.descriptorCount = 1;
    write.descriptorType = b.type;
    if (isImage(b.type) && given->image) {
      VkSampler sampler = b.type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER
                              ? context_->nearestSampler()
                              : nullptr;
      write.pImageInfo = &images.emplace_back(
          VkDescriptorImageInfo{sampler, given->image->view(), VK_IMAGE_LAYOUT_GENERAL});
    } else if (isBuffer(b.type) && given->buffer) {
      write.pBufferInfo = &buffers.emplace_back(given->buffer->descriptor());
    } else {
      throw std::logic_error(name_ + ": '" + b.name + "' is " +
                             (isImage(b.type) ? "an image" : "a buffer") + " in the shader");
    }
    writes.push_back(write);
  }
  for (const Bind& bind : binds)
    if (std::none_of(passBindings_.begin(), passBindings_.end(),
                     [&](const ShaderBinding& b) { return b.name == bind.name; }))
      throw std::logic_error(name_ + " has no binding '" + bind.name + "' (it has " +
                             namesOf(passBindings_) + ")");
  if (!writes.empty())
    context_->cmdPushDescriptorSet(cmd, bindPoint, layout_, kPassSet,
                                   static_cast<uint32_t>(writes.size()), writes.data());
  if (push.size) vkCmdPushConstants(cmd, layout_, kAllShaderStages, 0, push.size, push.data);
}

ComputeProgram::ComputeProgram(const Context& context, const std::string& shaderName,
                               const SetLayout* sceneSet,
                               std::initializer_list<Specialize> constants) {
  std::string key = shaderName + '|' + (sceneSet ? sceneSet->key() : "no scene");
  for (const Specialize& constant : constants)
    key += '|' + std::string(constant.name) + '=' + std::to_string(constant.value);
  compiled_ = context.shared<Compiled>(
      key, [&] { return compile(context, shaderName, sceneSet, constants); });
}

ComputeProgram::Compiled ComputeProgram::compile(const Context& context,
                                                 const std::string& shaderName,
                                                 const SetLayout* sceneSet,
                                                 std::initializer_list<Specialize> constants) {
  ShaderInterface interface = reflectShader(embeddedShader(shaderName));
  if (interface.stage != VK_SHADER_STAGE_COMPUTE_BIT)
    throw std::logic_error(shaderName + " is not a compute shader");
  Compiled compiled{stem(shaderName),
                    interface,
                    ProgramLayout(context, shaderName, std::span(&interface, 1), sceneSet),
                    {}};
  ShaderModule module = createShaderModule(context, shaderName);
  VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module;
  info.stage.pName = "main";
  std::vector<VkSpecializationMapEntry> entries;
  std::vector<uint32_t> values;
  for (const Specialize& constant : constants) {
    auto declared =
        std::find_if(interface.specConstants.begin(), interface.specConstants.end(),
                     [&](const ShaderSpecConstant& c) { return c.name == constant.name; });
    if (declared == interface.specConstants.end() || declared->size != sizeof(uint32_t))
      throw std::logic_error(compiled.name + " has no 32-bit specialization constant '" +
                             constant.name + "'");
    entries.push_back({declared->id, uint32_t(values.size() * sizeof(uint32_t)), sizeof(uint32_t)});
    values.push_back(constant.value);
  }
  VkSpecializationInfo specialization{uint32_t(entries.size()), entries.data(),
                                      values.size() * sizeof(uint32_t), values.data()};
  if (!entries.empty()) info.stage.pSpecializationInfo = &specialization;
  info.layout = compiled.layout.get();
  VkPipeline pipeline = VK_NULL_HANDLE;
  VK_CHECK(vkCreateComputePipelines(context.device(), context.pipelineCache(), 1, &info, nullptr,
                                    &pipeline));
  context.setName(VK_OBJECT_TYPE_PIPELINE, reinterpret_cast<uint64_t>(pipeline), shaderName);
  compiled.pipeline = Pipeline(context.device(), pipeline);
  return compiled;
}

void ComputeProgram::record(VkCommandBuffer cmd, std::span<const Bind> binds, const Grid& grid,
                            PushConstants push) const {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, compiled_->pipeline);
  compiled_->layout.bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, binds, push);
  if (grid.arguments) {
    vkCmdDispatchIndirect(cmd, grid.arguments->get(), grid.offset);
  } else {
    const std::array<uint32_t, 3>& size = compiled_->interface.localSize;
    vkCmdDispatch(cmd, (grid.x + size[0] - 1) / size[0], (grid.y + size[1] - 1) / size[1], 1);
  }
}

}  // namespace hdof::gpu
