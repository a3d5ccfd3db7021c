// Shader programs that know their own interface. A program reads its descriptor bindings, local
// size and push-constant size from its SPIR-V (gpu/shader_interface.h), so C++ states none of
// them: resources are bound by the shader's variable names, and a name, kind or push-constant
// size that does not match the shader is an error when the program is created or first recorded,
// never a wrong image. Set 0 is the scene (shared, bound as a descriptor set); set 1 is the
// pass's own bindings, pushed per dispatch (VK_KHR_push_descriptor).
#pragma once

#include "gpu/resources.h"
#include "gpu/shader_interface.h"

#include <initializer_list>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace hdof {
std::span<const uint32_t> embeddedShader(const std::string& name);  // generated at build time
std::vector<std::string> embeddedShaderNames();                     // every embedded shader
}  // namespace hdof

namespace hdof::gpu {

// The stages every descriptor and push-constant range of hdof is visible to.
inline constexpr VkShaderStageFlags kAllShaderStages =
    VK_SHADER_STAGE_COMPUTE_BIT | VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;

ShaderModule createShaderModule(const Context& context, const std::string& name);

// A descriptor set layout with the bindings it was made from (to check shaders against).
struct SetLayout {
  DescriptorSetLayout handle;
  std::vector<VkDescriptorSetLayoutBinding> bindings;
  // The bindings as text: pipelines made for one layout work with any layout of the same key.
  std::string key() const;
};

SetLayout createSetLayout(const Context& context,
                          std::vector<VkDescriptorSetLayoutBinding> bindings, bool pushDescriptors,
                          const std::string& name);

// A resource for the shader variable `name`: an image (storage, or sampled through the shared
// nearest sampler, as the shader declares it) or a buffer (uniform or storage).
struct Bind {
  Bind(const char* name, const Image& image) : name(name), image(&image) {}
  Bind(const char* name, const Buffer& buffer) : name(name), buffer(&buffer) {}
  const char* name;
  const Image* image = nullptr;
  const Buffer* buffer = nullptr;
};

// Push-constant bytes; their size must be the shader's push-constant block's.
struct PushConstants {
  PushConstants() = default;
  template <typename T>
  PushConstants(const T& value) : data(&value), size(sizeof(T)) {}
  const void* data = nullptr;
  uint32_t size = 0;
};

// How many workgroups a dispatch runs: enough to cover a grid of threads (in the shader's local
// size), or as many as a VkDispatchIndirectCommand in a buffer says.
struct Grid {
  static Grid threads(uint32_t x, uint32_t y = 1) { return {x, y, nullptr}; }
  static Grid over(const Image& image) { return threads(image.width(), image.height()); }
  static Grid indirect(const Buffer& arguments, VkDeviceSize offset = 0) {
    return {0, 0, &arguments, offset};
  }
  uint32_t x, y;
  const Buffer* arguments;
  VkDeviceSize offset = 0;  // of the VkDispatchIndirectCommand in `arguments`
};

// The pipeline layout of one or more shader stages: set 0 the scene's (when a stage reads it),
// set 1 the stages' own bindings as push descriptors, and their push constants.
class ProgramLayout {
 public:
  ProgramLayout(const Context& context, const std::string& name,
                std::span<const ShaderInterface> stages, const SetLayout* sceneSet);

  VkPipelineLayout get() const { return layout_; }
  bool readsScene() const { return readsScene_; }
  // Pushes set 1 and the push constants. Every binding of set 1 must be given exactly once.
  void bind(VkCommandBuffer cmd, VkPipelineBindPoint bindPoint, std::span<const Bind> binds,
            PushConstants push) const;

 private:
  const Context* context_;
  std::string name_;
  std::vector<ShaderBinding> passBindings_;
  uint32_t pushConstantSize_ = 0;
  bool readsScene_ = false;
  SetLayout passSet_, emptySet_;
  PipelineLayout layout_;
};

// The value of a shader's specialization constant, named as the shader names it: a bool (0 or 1)
// or a 32-bit integer. One shader made into pipelines for different cases, each without the code
// that its case never runs.
struct Specialize {
  const char* name;
  uint32_t value;
};

// A compute shader (shaders/NAME.comp, embedded) with its pipeline. Programs of the same shader,
// constants and scene layout share one pipeline, made by the first (Context::shared).
class ComputeProgram {
 public:
  // sceneSet: the scene's set layout, required when the shader reads set 0. constants: values for
  // some of the shader's specialization constants (the others keep their defaults); a name the
  // shader does not declare is an error.
  ComputeProgram(const Context& context, const std::string& shaderName,
                 const SetLayout* sceneSet = nullptr,
                 std::initializer_list<Specialize> constants = {});

  // The shader's file name without its extension: "dof_gather".
  const std::string& name() const { return compiled_->name; }
  const ShaderInterface& interface() const { return compiled_->interface; }
  bool readsScene() const { return compiled_->layout.readsScene(); }
  VkPipelineLayout layout() const { return compiled_->layout.get(); }

  // Binds the pipeline, pushes binds and push constants, and dispatches grid. The scene's set
  // (when the shader reads it) is the caller's to bind.
  void record(VkCommandBuffer cmd, std::span<const Bind> binds, const Grid& grid,
              PushConstants push = {}) const;

 private:
  struct Compiled {
    std::string name;
    ShaderInterface interface;
    ProgramLayout layout;
    Pipeline pipeline;
  };
  static Compiled compile(const Context& context, const std::string& shaderName,
                          const SetLayout* sceneSet, std::initializer_list<Specialize> constants);

  std::shared_ptr<const Compiled> compiled_;
};

}  // namespace hdof::gpu
