// A small SPIR-V reader: one pass records the definitions, names and decorations of ids, then the
// interface is read from the module's variables. Numbers are the SPIR-V specification's
// enumerants (section 3 of the unified specification).
#include "gpu/shader_interface.h"

#include <algorithm>
#include <iterator>
#include <stdexcept>
#include <unordered_map>
#include <utility>

namespace hdof::gpu {
namespace {

constexpr uint32_t kMagic = 0x07230203;

// Opcodes.
constexpr uint32_t kOpName = 5, kOpEntryPoint = 15, kOpExecutionMode = 16, kOpTypeBool = 20,
                   kOpTypeInt = 21, kOpTypeFloat = 22, kOpTypeVector = 23, kOpTypeMatrix = 24,
                   kOpTypeImage = 25, kOpTypeSampler = 26, kOpTypeSampledImage = 27,
                   kOpTypeArray = 28, kOpTypeRuntimeArray = 29, kOpTypeStruct = 30,
                   kOpTypePointer = 32, kOpConstant = 43, kOpConstantComposite = 44,
                   kOpSpecConstantTrue = 48, kOpSpecConstantFalse = 49, kOpSpecConstant = 50, kOpSpecConstantComposite = 51, kOpVariable = 59,
                   kOpDecorate = 71, kOpMemberDecorate = 72, kOpExecutionModeId = 331,
                   kOpTypeAccelerationStructureKHR = 5341;
// Decorations.
constexpr uint32_t kDecorationSpecId = 1, kDecorationBlock = 2, kDecorationBufferBlock = 3, kDecorationRowMajor = 4,
                   kDecorationArrayStride = 6, kDecorationMatrixStride = 7, kDecorationBuiltIn = 11,
                   kDecorationBinding = 33, kDecorationDescriptorSet = 34, kDecorationOffset = 35;
// Storage classes.
constexpr uint32_t kUniformConstant = 0, kUniform = 2, kPushConstant = 9, kStorageBuffer = 12;
constexpr uint32_t kBuiltInWorkgroupSize = 25;
constexpr uint32_t kExecutionModeLocalSize = 17, kExecutionModeLocalSizeId = 38;
constexpr uint32_t kDimBuffer = 5, kDimSubpassData = 6;
// Execution models 0 to 5: Vertex, TessellationControl, TessellationEvaluation, Geometry,
// Fragment, GLCompute.
constexpr VkShaderStageFlagBits kStages[] = {VK_SHADER_STAGE_VERTEX_BIT,
                                             VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT,
                                             VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT,
                                             VK_SHADER_STAGE_GEOMETRY_BIT,
                                             VK_SHADER_STAGE_FRAGMENT_BIT,
                                             VK_SHADER_STAGE_COMPUTE_BIT};
// SPIR-V's universal limit on a struct's members; also bounds what a malformed module allocates.
constexpr uint32_t kMaxStructMembers = 16383;
// Types nest this deep only when a malformed module defines a type through itself.
constexpr int kMaxTypeDepth = 64;

using Instruction = std::span<const uint32_t>;

[[noreturn]] void fail(const std::string& message) {
  throw std::runtime_error("SPIR-V: " + message);
}

uint32_t opcodeOf(Instruction ins) { return ins.empty() ? 0 : ins[0] & 0xffff; }

// Operand `i` of an instruction (word 0 is the opcode and word count).
uint32_t word(Instruction ins, size_t i) {
  if (i >= ins.size()) fail("instruction " + std::to_string(opcodeOf(ins)) + " too short");
  return ins[i];
}

// A literal string: UTF-8, nul-terminated, packed four bytes a word, first byte lowest.
std::string literalString(Instruction ins, size_t first) {
  std::string text;
  for (size_t i = first; i < ins.size(); ++i)
    for (int byte = 0; byte < 4; ++byte) {
      char c = static_cast<char>((ins[i] >> (8 * byte)) & 0xff);
      if (c == '\0') return text;
      text += c;
    }
  fail("unterminated string");
}

struct MemberLayout {
  uint32_t offset = 0;
  uint32_t matrixStride = 0;
  bool rowMajor = false;
};

// What the module says about one id.
struct Id {
  Instruction def;  // the type, constant or variable instruction that defines it
  std::string name;
  uint32_t set = 0;
  uint32_t binding = 0;
  bool block = false;
  bool bufferBlock = false;
  bool workgroupSize = false;
  bool specId = false;  // decorated SpecId: a specialization constant's
  uint32_t specIdValue = 0;
  uint32_t arrayStride = 0;
  std::vector<MemberLayout> members;  // of a struct
};

struct Module {
  std::unordered_map<uint32_t, Id> ids;
  std::vector<uint32_t> variables;
  std::vector<uint32_t> specConstants;
  Instruction entryPoint;
  std::vector<Instruction> executionModes;

  const Id& at(uint32_t id) const {
    auto it = ids.find(id);
    if (it == ids.end() || it->second.def.empty()) fail("id " + std::to_string(id) + " undefined");
    return it->second;
  }
  // The defining instruction of `id`, which must be `opcode`.
  Instruction def(uint32_t id, uint32_t opcode) const {
    Instruction ins = at(id).def;
    if (opcodeOf(ins) != opcode)
      fail("id " + std::to_string(id) + " is not an instruction " + std::to_string(opcode));
    return ins;
  }
  // The value of an integer constant (specialization constants: their default).
  uint32_t constant(uint32_t id) const {
    Instruction ins = at(id).def;
    if (opcodeOf(ins) != kOpConstant && opcodeOf(ins) != kOpSpecConstant)
      fail("id " + std::to_string(id) + " is not a constant");
    return word(ins, 3);
  }
};

void decorate(Id& target, Instruction ins) {
  switch (word(ins, 2)) {
    case kDecorationSpecId:
      target.specId = true;
      target.specIdValue = word(ins, 3);
      break;
    case kDecorationDescriptorSet:
      target.set = word(ins, 3);
      break;
    case kDecorationBinding:
      target.binding = word(ins, 3);
      break;
    case kDecorationBlock:
      target.block = true;
      break;
    case kDecorationBufferBlock:
      target.bufferBlock = true;
      break;
    case kDecorationArrayStride:
      target.arrayStride = word(ins, 3);
      break;
    case kDecorationBuiltIn:
      target.workgroupSize |= word(ins, 3) == kBuiltInWorkgroupSize;
      break;
  }
}

void decorateMember(Id& target, Instruction ins) {
  uint32_t member = word(ins, 2);
  if (member >= kMaxStructMembers) fail("struct member " + std::to_string(member));
  if (target.members.size() <= member) target.members.resize(member + 1);
  MemberLayout& layout = target.members[member];
  switch (word(ins, 3)) {
    case kDecorationOffset:
      layout.offset = word(ins, 4);
      break;
    case kDecorationMatrixStride:
      layout.matrixStride = word(ins, 4);
      break;
    case kDecorationRowMajor:
      layout.rowMajor = true;
      break;
  }
}

Module parse(std::span<const uint32_t> spirv) {
  if (spirv.size() < 5) fail("shorter than its header");
  if (spirv[0] != kMagic) fail("bad magic number");
  Module module;
  for (size_t at = 5; at < spirv.size();) {
    uint32_t wordCount = spirv[at] >> 16;
    if (wordCount == 0 || wordCount > spirv.size() - at)
      fail("truncated instruction at word " + std::to_string(at));
    Instruction ins = spirv.subspan(at, wordCount);
    at += wordCount;
    switch (uint32_t opcode = opcodeOf(ins)) {
      case kOpName:
        module.ids[word(ins, 1)].name = literalString(ins, 2);
        break;
      case kOpEntryPoint:
        if (module.entryPoint.empty()) module.entryPoint = ins;
        break;
      case kOpExecutionMode:
      case kOpExecutionModeId:
        module.executionModes.push_back(ins);
        break;
      case kOpDecorate:
        decorate(module.ids[word(ins, 1)], ins);
        break;
      case kOpMemberDecorate:
        decorateMember(module.ids[word(ins, 1)], ins);
        break;
      case kOpSpecConstantTrue:
      case kOpSpecConstantFalse:
      case kOpSpecConstant:
        module.specConstants.push_back(word(ins, 2));
        [[fallthrough]];
      case kOpConstant:
      case kOpConstantComposite:
      case kOpSpecConstantComposite:
        module.ids[word(ins, 2)].def = ins;
        break;
      case kOpVariable:
        module.ids[word(ins, 2)].def = ins;
        module.variables.push_back(word(ins, 2));
        break;
      default:
        // Types define their result in word 1.
        if ((opcode >= kOpTypeBool && opcode <= kOpTypePointer) ||
            opcode == kOpTypeAccelerationStructureKHR)
          module.ids[word(ins, 1)].def = ins;
    }
  }
  if (module.entryPoint.empty()) fail("no entry point");
  return module;
}

std::array<uint32_t, 3> localSizeOf(const Module& module) {
  std::array<uint32_t, 3> size{1, 1, 1};
  uint32_t function = word(module.entryPoint, 2);
  for (Instruction mode : module.executionModes) {
    bool literals = opcodeOf(mode) == kOpExecutionMode && word(mode, 2) == kExecutionModeLocalSize;
    bool ids = opcodeOf(mode) == kOpExecutionModeId && word(mode, 2) == kExecutionModeLocalSizeId;
    if (word(mode, 1) != function || (!literals && !ids)) continue;
    for (uint32_t i = 0; i < 3; ++i)
      size[i] = literals ? word(mode, 3 + i) : module.constant(word(mode, 3 + i));
  }
  // A constant decorated BuiltIn WorkgroupSize takes precedence over the execution mode (GLSL's
  // local_size_x_id makes one, so that specialization can change the size).
  for (const auto& [id, info] : module.ids) {
    if (!info.workgroupSize) continue;
    uint32_t opcode = opcodeOf(module.at(id).def);
    if (opcode != kOpConstantComposite && opcode != kOpSpecConstantComposite)
      fail("WorkgroupSize is not a composite constant");
    for (uint32_t i = 0; i < 3; ++i) size[i] = module.constant(word(info.def, 3 + i));
  }
  return size;
}

// Bytes from the start of a value of `type` to the end of its last byte, inside a block; `layout`
// is that of the struct member holding it (for matrices).
uint32_t sizeOf(const Module& module, uint32_t type, const MemberLayout& layout, int depth) {
  if (depth > kMaxTypeDepth) fail("types nested too deep");
  const Id& info = module.at(type);
  Instruction def = info.def;
  switch (opcodeOf(def)) {
    case kOpTypeInt:
    case kOpTypeFloat:
      return word(def, 2) / 8;
    case kOpTypeVector:
      return word(def, 3) * sizeOf(module, word(def, 2), layout, depth + 1);
    case kOpTypeMatrix: {
      // MatrixStride separates columns, or rows when the member is decorated RowMajor.
      uint32_t columns = word(def, 3);
      uint32_t rows = word(module.def(word(def, 2), kOpTypeVector), 3);
      return (layout.rowMajor ? rows : columns) * layout.matrixStride;
    }
    case kOpTypeArray: {
      uint32_t length = module.constant(word(def, 3));
      uint32_t stride = info.arrayStride;
      return length * (stride ? stride : sizeOf(module, word(def, 2), layout, depth + 1));
    }
    case kOpTypeStruct: {
      uint32_t size = 0;
      for (size_t i = 2; i < def.size(); ++i) {
        size_t member = i - 2;
        MemberLayout memberLayout =
            member < info.members.size() ? info.members[member] : MemberLayout{};
        size =
            std::max(size, memberLayout.offset + sizeOf(module, def[i], memberLayout, depth + 1));
      }
      return size;
    }
  }
  fail("no size for type " + std::to_string(type));
}

VkDescriptorType descriptorType(const Module& module, uint32_t storageClass, uint32_t type) {
  const Id& info = module.at(type);
  Instruction def = info.def;
  switch (storageClass) {
    case kUniform:
      if (info.block) return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
      // A storage buffer as SPIR-V before 1.3 declares it (it had no StorageBuffer class).
      if (info.bufferBlock) return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      break;
    case kStorageBuffer:
      return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    case kUniformConstant:
      switch (opcodeOf(def)) {
        case kOpTypeSampler:
          return VK_DESCRIPTOR_TYPE_SAMPLER;
        case kOpTypeSampledImage: {
          // GLSL's samplerBuffer: a texel buffer, though SPIR-V types it as a sampled image.
          uint32_t dim = word(module.def(word(def, 2), kOpTypeImage), 3);
          return dim == kDimBuffer ? VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER
                                   : VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        }
        case kOpTypeImage: {
          // Operand Sampled: 1 for an image read through a sampler, 2 for a storage image.
          uint32_t dim = word(def, 3), sampled = word(def, 7);
          if (dim == kDimSubpassData) return VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT;
          if (sampled == 2)
            return dim == kDimBuffer ? VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER
                                     : VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
          if (sampled == 1)
            return dim == kDimBuffer ? VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER
                                     : VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
          break;
        }
        case kOpTypeAccelerationStructureKHR:
          return VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
      }
      break;
  }
  fail("unknown type " + std::to_string(type) + " for a descriptor");
}

}  // namespace

const ShaderBinding* ShaderInterface::find(std::string_view name) const {
  auto it = std::find_if(bindings.begin(), bindings.end(),
                         [name](const ShaderBinding& b) { return b.name == name; });
  return it == bindings.end() ? nullptr : &*it;
}

std::vector<ShaderBinding> ShaderInterface::bindingsOf(uint32_t set) const {
  std::vector<ShaderBinding> result;
  std::copy_if(bindings.begin(), bindings.end(), std::back_inserter(result),
               [set](const ShaderBinding& b) { return b.set == set; });
  return result;
}

ShaderInterface reflectShader(std::span<const uint32_t> spirv) {
  Module module = parse(spirv);
  ShaderInterface result;
  uint32_t executionModel = word(module.entryPoint, 1);
  if (executionModel >= std::size(kStages))
    fail("unsupported execution model " + std::to_string(executionModel));
  result.stage = kStages[executionModel];
  result.localSize = localSizeOf(module);
  for (uint32_t id : module.variables) {
    const Id& variable = module.at(id);
    uint32_t storageClass = word(variable.def, 3);
    if (storageClass != kUniformConstant && storageClass != kUniform &&
        storageClass != kPushConstant && storageClass != kStorageBuffer)
      continue;  // inputs, outputs, workgroup and function memory
    uint32_t type = word(module.def(word(variable.def, 1), kOpTypePointer), 3);
    if (storageClass == kPushConstant) {
      result.pushConstantSize = std::max(result.pushConstantSize, sizeOf(module, type, {}, 0));
      continue;
    }
    ShaderBinding binding;
    binding.name = variable.name;
    binding.set = variable.set;
    binding.binding = variable.binding;
    // An array of descriptors (of any dimensions) is one binding of that many descriptors.
    for (int depth = 0;; ++depth) {
      Instruction def = module.at(type).def;
      if (opcodeOf(def) == kOpTypeArray)
        binding.count *= module.constant(word(def, 3));
      else if (opcodeOf(def) == kOpTypeRuntimeArray)
        binding.count = 0;
      else
        break;
      if (depth > kMaxTypeDepth) fail("types nested too deep");
      type = word(def, 2);
    }
    binding.type = descriptorType(module, storageClass, type);
    // glslang names the instance of a block declared without one "" (or not at all).
    if (binding.name.empty()) binding.name = module.at(type).name;
    result.bindings.push_back(std::move(binding));
  }
  std::sort(result.bindings.begin(), result.bindings.end(), [](const auto& a, const auto& b) {
    return std::pair(a.set, a.binding) < std::pair(b.set, b.binding);
  });
  for (uint32_t id : module.specConstants) {
    const Id& constant = module.at(id);
    if (!constant.specId) continue;  // a default that no SpecId makes specializable
    uint32_t size = 4;
    if (opcodeOf(constant.def) == kOpSpecConstant)
      size = sizeOf(module, word(constant.def, 1), {}, 0);
    result.specConstants.push_back({constant.name, constant.specIdValue, size});
  }
  std::sort(result.specConstants.begin(), result.specConstants.end(),
            [](const auto& a, const auto& b) { return a.id < b.id; });
  return result;
}

}  // namespace hdof::gpu
