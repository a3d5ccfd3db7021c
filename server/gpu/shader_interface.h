// A shader's interface read from its SPIR-V: descriptor bindings, workgroup size, push-constant
// size and specialization constants, so that C++ does not restate what the GLSL declares.
#pragma once

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hdof::gpu {

struct ShaderBinding {
  std::string name;  // the variable's name; for an anonymous block instance, the block's type name
  uint32_t set = 0;
  uint32_t binding = 0;
  VkDescriptorType type = VK_DESCRIPTOR_TYPE_MAX_ENUM;
  uint32_t count = 1;  // array length for arrays of descriptors, 0 for a runtime-sized array
};

// A specialization constant (GLSL `layout(constant_id = N) const bool kName = ...`).
struct ShaderSpecConstant {
  std::string name;
  uint32_t id = 0;    // its SpecId
  uint32_t size = 4;  // bytes of its value: 4 for a bool (VkBool32) or a 32-bit number
};

struct ShaderInterface {
  VkShaderStageFlagBits stage = VK_SHADER_STAGE_COMPUTE_BIT;  // from OpEntryPoint's execution model
  std::vector<ShaderBinding> bindings;                        // sorted by (set, binding)
  std::array<uint32_t, 3> localSize{1, 1, 1};                 // compute shaders
  uint32_t pushConstantSize = 0;  // bytes of the push-constant block, 0 if none
  std::vector<ShaderSpecConstant> specConstants;  // sorted by id

  // The binding named `name`, or nullptr.
  const ShaderBinding* find(std::string_view name) const;
  // Bindings of one set, in binding order.
  std::vector<ShaderBinding> bindingsOf(uint32_t set) const;
};

// Reads a module's interface (of its first entry point; every variable of the module counts);
// throws std::runtime_error with a one-line message on malformed SPIR-V (bad magic, truncated
// instruction, unknown type for a descriptor).
ShaderInterface reflectShader(std::span<const uint32_t> spirv);

}  // namespace hdof::gpu
