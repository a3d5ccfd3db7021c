// SPIR-V reflection, on the shaders embedded at build time and on small hand-assembled modules.
#include "gpu/shader_interface.h"

#include "gpu/program.h"

#include <gtest/gtest.h>

#include <initializer_list>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace hdof::gpu {
namespace {

ShaderInterface reflect(const std::string& name) { return reflectShader(embeddedShader(name)); }

void expectBinding(const ShaderInterface& shader, const std::string& name, uint32_t set,
                   uint32_t binding, VkDescriptorType type) {
  const ShaderBinding* b = shader.find(name);
  ASSERT_NE(b, nullptr) << name;
  EXPECT_EQ(b->set, set) << name;
  EXPECT_EQ(b->binding, binding) << name;
  EXPECT_EQ(b->type, type) << name;
  EXPECT_EQ(b->count, 1u) << name;
}

TEST(ShaderInterface, HybridTemporal) {
  ShaderInterface shader = reflect("hybrid_temporal.comp");
  EXPECT_EQ(shader.stage, VK_SHADER_STAGE_COMPUTE_BIT);
  EXPECT_EQ(shader.localSize, (std::array<uint32_t, 3>{64, 1, 1}));
  EXPECT_EQ(shader.pushConstantSize, 8u);
  EXPECT_TRUE(shader.bindingsOf(0).empty());
  const std::vector<std::pair<std::string, VkDescriptorType>> expected = {
      {"Frame", VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
      {"rays", VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {"nearLayer", VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {"farLayer", VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {"farPosition", VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {"motion", VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {"normalDepth", VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {"historyNear", VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {"historyFar", VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {"historyMoments", VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {"workList", VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {"outNear", VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {"outFar", VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {"outMoments", VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {"outVariance", VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
  };
  std::vector<ShaderBinding> set1 = shader.bindingsOf(1);
  ASSERT_EQ(set1.size(), expected.size());
  for (uint32_t i = 0; i < set1.size(); ++i) {
    EXPECT_EQ(set1[i].name, expected[i].first);
    EXPECT_EQ(set1[i].set, 1u);
    EXPECT_EQ(set1[i].binding, i);
    EXPECT_EQ(set1[i].type, expected[i].second) << set1[i].name;
    EXPECT_EQ(set1[i].count, 1u);
  }
}

TEST(ShaderInterface, DofDownsample) {
  ShaderInterface shader = reflect("dof_downsample.comp");
  EXPECT_EQ(shader.localSize, (std::array<uint32_t, 3>{8, 8, 1}));
  EXPECT_EQ(shader.pushConstantSize, 0u);
  EXPECT_EQ(shader.bindings.size(), 5u);
  expectBinding(shader, "Frame", 1, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER);
  expectBinding(shader, "color", 1, 1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
  expectBinding(shader, "normalDepth", 1, 2, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
  expectBinding(shader, "colorCoc", 1, 3, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
  expectBinding(shader, "halfColorCoc", 1, 4, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
  EXPECT_EQ(shader.find("frame"), nullptr);  // the block's instance name is not its name
  EXPECT_EQ(shader.find("noSuchBinding"), nullptr);
}

TEST(ShaderInterface, HybridTraceReadsTheScene) {
  ShaderInterface shader = reflect("hybrid_trace.comp");
  expectBinding(shader, "vertexTexels", 0, 0, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER);
  expectBinding(shader, "triangleTexels", 0, 1, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER);
  expectBinding(shader, "materialTexels", 0, 2, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER);
  expectBinding(shader, "lightTexels", 0, 3, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER);
  expectBinding(shader, "bvhNodeTexels", 0, 4, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER);
  expectBinding(shader, "bvhTriangleTexels", 0, 5, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER);
  expectBinding(shader, "textures", 0, 6, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
  expectBinding(shader, "workList", 1, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  expectBinding(shader, "samplesTraced", 1, 6, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
  EXPECT_EQ(shader.localSize, (std::array<uint32_t, 3>{64, 1, 1}));
  for (size_t i = 1; i < shader.bindings.size(); ++i)
    EXPECT_LT(std::pair(shader.bindings[i - 1].set, shader.bindings[i - 1].binding),
              std::pair(shader.bindings[i].set, shader.bindings[i].binding));
}

TEST(ShaderInterface, StageAndPushConstants) {
  EXPECT_EQ(reflect("gbuffer.vert").stage, VK_SHADER_STAGE_VERTEX_BIT);
  EXPECT_EQ(reflect("gbuffer.frag").stage, VK_SHADER_STAGE_FRAGMENT_BIT);
  EXPECT_EQ(reflect("reference.comp").pushConstantSize, 16u);
}

TEST(ShaderInterface, EveryEmbeddedShaderReflects) {
  std::vector<std::string> names = embeddedShaderNames();
  EXPECT_GT(names.size(), 10u);
  for (const std::string& name : names) {
    ShaderInterface shader;
    ASSERT_NO_THROW(shader = reflect(name)) << name;
    if (shader.stage != VK_SHADER_STAGE_COMPUTE_BIT) continue;
    std::set<std::pair<uint32_t, uint32_t>> slots;
    std::set<std::string> bindingNames;
    for (const ShaderBinding& b : shader.bindings) {
      EXPECT_TRUE(slots.insert({b.set, b.binding}).second)
          << name << ": set " << b.set << " binding " << b.binding << " twice";
      EXPECT_TRUE(bindingNames.insert(b.name).second) << name << ": " << b.name << " twice";
      EXPECT_FALSE(b.name.empty()) << name;
    }
  }
}

TEST(ShaderInterface, MalformedModulesThrow) {
  EXPECT_THROW(reflectShader({}), std::runtime_error);
  std::vector<uint32_t> words(embeddedShader("tonemap.comp").begin(),
                              embeddedShader("tonemap.comp").end());
  std::vector<uint32_t> badMagic = words;
  badMagic[0] = 0x03022307;  // the magic number byte-swapped
  EXPECT_THROW(reflectShader(badMagic), std::runtime_error);
  // Cut inside the first instruction of more than two words.
  size_t at = 5;
  while ((words[at] >> 16) <= 2) at += words[at] >> 16;
  words.resize(at + 2);
  EXPECT_THROW(reflectShader(words), std::runtime_error);
}

// A compute module assembled by hand, to cover what the embedded shaders do not declare.
class Module {
 public:
  Module() {
    op(15, {5, 1, 0x6e69616d, 0});  // OpEntryPoint GLCompute %1 "main"
    op(21, {2, 32, 0});             // %2 = OpTypeInt 32 unsigned
    op(22, {3, 32});                // %3 = OpTypeFloat 32
    for (uint32_t value : {4u, 2u, 1u}) op(43, {2, 10 + value, value});  // %14 %12 %11: 4, 2, 1
  }
  Module& op(uint32_t opcode, std::initializer_list<uint32_t> operands) {
    words_.push_back(static_cast<uint32_t>(operands.size() + 1) << 16 | opcode);
    words_.insert(words_.end(), operands);
    return *this;
  }
  ShaderInterface reflect() const { return reflectShader(words_); }

 private:
  std::vector<uint32_t> words_{0x07230203, 0x00010500, 0, 100, 0};
};

TEST(ShaderInterface, LocalSizeFromIdsAndWorkgroupSize) {
  Module module;
  module.op(331, {1, 38, 14, 12, 11});  // OpExecutionModeId %1 LocalSizeId %14 %12 %11
  EXPECT_EQ(module.reflect().localSize, (std::array<uint32_t, 3>{4, 2, 1}));
  module.op(23, {4, 2, 3});            // %4 = OpTypeVector %2 3
  module.op(51, {4, 20, 12, 12, 14});  // %20 = OpSpecConstantComposite %4 %12 %12 %14
  module.op(71, {20, 11, 25});         // OpDecorate %20 BuiltIn WorkgroupSize
  EXPECT_EQ(module.reflect().localSize, (std::array<uint32_t, 3>{2, 2, 4}));
}

TEST(ShaderInterface, SpecializationConstants) {
  ShaderInterface composite = reflect("dof_composite.comp");
  ASSERT_EQ(composite.specConstants.size(), 1u);
  EXPECT_EQ(composite.specConstants[0].name, "kList");
  EXPECT_EQ(composite.specConstants[0].id, 0u);
  EXPECT_EQ(composite.specConstants[0].size, 4u);
  EXPECT_TRUE(reflect("dof_composite_layers.comp").specConstants.empty());

  Module module;
  module.op(20, {4});                  // %4 = OpTypeBool
  module.op(48, {4, 30});              // %30 = OpSpecConstantTrue %4
  module.op(50, {3, 31, 0x3f800000});  // %31 = OpSpecConstant %3 1.0
  module.op(49, {4, 32});              // %32 = OpSpecConstantFalse %4, no SpecId: not listed
  module.op(5, {30, 0x0000616b});      // OpName %30 "ka"
  module.op(5, {31, 0x0000626b});      // OpName %31 "kb"
  module.op(71, {31, 1, 3});           // OpDecorate %31 SpecId 3
  module.op(71, {30, 1, 7});           // OpDecorate %30 SpecId 7
  ShaderInterface shader = module.reflect();
  ASSERT_EQ(shader.specConstants.size(), 2u);
  EXPECT_EQ(shader.specConstants[0].name, "kb");
  EXPECT_EQ(shader.specConstants[0].id, 3u);
  EXPECT_EQ(shader.specConstants[1].name, "ka");
  EXPECT_EQ(shader.specConstants[1].id, 7u);
}

TEST(ShaderInterface, ArraysBufferBlocksAndMatrices) {
  Module module;
  module.op(25, {5, 3, 1, 0, 0, 0, 1, 0});  // %5 = OpTypeImage %3 2D, sampled
  module.op(27, {6, 5});                    // %6 = OpTypeSampledImage %5
  module.op(28, {7, 6, 14});                // %7 = OpTypeArray %6 %14
  module.op(32, {8, 0, 7});                 // %8 = OpTypePointer UniformConstant %7
  module.op(59, {8, 30, 0});                // %30 = OpVariable %8 UniformConstant
  module.op(5, {30, 0x00786574});           // OpName %30 "tex"
  module.op(71, {30, 34, 2}).op(71, {30, 33, 3});
  // An anonymous `buffer` block as older SPIR-V writes it: Uniform, decorated BufferBlock.
  module.op(30, {9, 3});                           // %9 = OpTypeStruct %3
  module.op(5, {9, 0x00646c4f}).op(71, {9, 3});    // OpName %9 "Old"; BufferBlock
  module.op(32, {15, 2, 9}).op(59, {15, 31, 2});   // %31: Uniform %9
  module.op(71, {31, 34, 0}).op(71, {31, 33, 5});  // set 0, binding 5
  // Push constants { float a; mat4 m (MatrixStride 16) at 16; } = 80 bytes.
  module.op(23, {16, 3, 4}).op(24, {17, 16, 4});  // %16 = vec4, %17 = mat4
  module.op(30, {18, 3, 17});                     // %18 = OpTypeStruct %3 %17
  module.op(72, {18, 0, 35, 0}).op(72, {18, 1, 35, 16}).op(72, {18, 1, 7, 16});
  module.op(32, {19, 9, 18}).op(59, {19, 32, 9});  // %32: PushConstant %18
  ShaderInterface shader = module.reflect();
  ASSERT_EQ(shader.bindings.size(), 2u);
  EXPECT_EQ(shader.bindings[0].name, "Old");
  EXPECT_EQ(shader.bindings[0].type, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  EXPECT_EQ(shader.bindings[0].binding, 5u);
  EXPECT_EQ(shader.bindings[1].name, "tex");
  EXPECT_EQ(shader.bindings[1].type, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
  EXPECT_EQ(shader.bindings[1].set, 2u);
  EXPECT_EQ(shader.bindings[1].binding, 3u);
  EXPECT_EQ(shader.bindings[1].count, 4u);
  EXPECT_EQ(shader.pushConstantSize, 80u);
  EXPECT_EQ(shader.localSize, (std::array<uint32_t, 3>{1, 1, 1}));
}

TEST(ShaderInterface, UnknownDescriptorTypeThrows) {
  Module module;
  module.op(32, {4, 0, 3}).op(59, {4, 20, 0});  // a float in UniformConstant
  module.op(71, {20, 33, 0});
  EXPECT_THROW(module.reflect(), std::runtime_error);
}

}  // namespace
}  // namespace hdof::gpu
