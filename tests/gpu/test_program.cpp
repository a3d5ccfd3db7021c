// Compute programs know their shader's interface: what C++ binds is checked against it by name,
// kind and push-constant size, so a mismatch is an error rather than a wrong image.
#include "gpu/program.h"
#include "render/frame_images.h"
#include "render_fixture.h"

#include <gtest/gtest.h>

#include <shared/dof.h>
#include <shared/frame.h>

#include <stdexcept>
#include <string>

namespace hdof::test {
namespace {

// Records into a command buffer that is never submitted.
class Recording {
 public:
  Recording() : cmd_(testContext().allocateCommandBuffer()) {
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    VK_CHECK(vkBeginCommandBuffer(cmd_, &begin));
  }
  ~Recording() {
    vkEndCommandBuffer(cmd_);
    vkResetCommandBuffer(cmd_, 0);
  }
  VkCommandBuffer cmd() const { return cmd_; }

 private:
  VkCommandBuffer cmd_;
};

std::string errorOf(const std::function<void()>& record) {
  try {
    record();
  } catch (const std::logic_error& e) {
    return e.what();
  }
  return "";
}

TEST(ComputeProgram, TakesItsInterfaceFromTheShader) {
  gpu::ComputeProgram tiles(testContext(), "dof_tiles.comp");
  EXPECT_EQ(tiles.name(), "dof_tiles");
  EXPECT_EQ(tiles.interface().localSize, (std::array<uint32_t, 3>{8, 8, 1}));
  EXPECT_FALSE(tiles.readsScene());
  SceneOnGpu& scene = testScene("builtin:wall");
  gpu::ComputeProgram trace(testContext(), "hybrid_trace.comp", &scene.gpu->setLayout());
  EXPECT_TRUE(trace.readsScene());
  EXPECT_EQ(trace.interface().localSize[0], 64u);
}

TEST(ComputeProgram, ABindingThatDoesNotMatchTheShaderIsAnError) {
  gpu::ComputeProgram dilate(testContext(), "dof_dilate.comp");
  FrameImages images(testContext(), 32, 16);
  gpu::Buffer frame(testContext(), sizeof(gpu::FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                    gpu::MemoryUse::Upload, "test frame");
  Recording recording;
  auto record = [&](std::initializer_list<gpu::Bind> binds, gpu::PushConstants push = {}) {
    return errorOf(
        [&] { dilate.record(recording.cmd(), binds, gpu::Grid::over(images.dof.tiles), push); });
  };
  EXPECT_EQ(
      record({{"Frame", frame}, {"tiles", images.dof.tiles}, {"dilated", images.dof.dilatedTiles}}),
      "");
  EXPECT_NE(
      record({{"Frame", frame}, {"tiles", images.dof.tiles}}).find("nothing bound to 'dilated'"),
      std::string::npos);
  EXPECT_NE(record({{"Frame", frame},
                    {"tiles", images.dof.tiles},
                    {"dilated", images.dof.dilatedTiles},
                    {"dilate", images.dof.dilatedTiles}})
                .find("no binding 'dilate'"),
            std::string::npos);
  EXPECT_NE(record({{"Frame", frame}, {"tiles", frame}, {"dilated", images.dof.dilatedTiles}})
                .find("'tiles' is an image"),
            std::string::npos);
  EXPECT_NE(record({{"Frame", frame},
                    {"tiles", images.dof.tiles},
                    {"tiles", images.dof.tiles},
                    {"dilated", images.dof.dilatedTiles}})
                .find("bound twice"),
            std::string::npos);
  uint32_t unexpected = 1;
  EXPECT_NE(
      record({{"Frame", frame}, {"tiles", images.dof.tiles}, {"dilated", images.dof.dilatedTiles}},
             unexpected)
          .find("push constants"),
      std::string::npos);
}

TEST(ComputeProgram, SpecializesConstantsByName) {
  EXPECT_EQ(errorOf([] {
              gpu::ComputeProgram(testContext(), "dof_composite.comp", nullptr,
                                  {{"kList", gpu::kDofListNarrow}});
            }),
            "");
  std::string error = errorOf([] {
    gpu::ComputeProgram(testContext(), "dof_composite.comp", nullptr, {{"kLists", 0}});
  });
  EXPECT_NE(error.find("no 32-bit specialization constant 'kLists'"), std::string::npos) << error;
}

TEST(ComputeProgram, ProgramsOfOneShaderConstantsAndSceneLayoutShareAPipeline) {
  SceneOnGpu& wall = testScene("builtin:wall");
  SceneOnGpu& dof = testScene("builtin:dof");
  auto resolveLayout = [&](SceneOnGpu& scene, uint32_t step) {
    return gpu::ComputeProgram(testContext(), "gbuffer_resolve.comp", &scene.gpu->setLayout(),
                               {{"kStep", step}})
        .layout();
  };
  // Another scene's set layout has the same bindings: its programs are the same.
  EXPECT_EQ(resolveLayout(wall, 1), resolveLayout(dof, 1));
  EXPECT_NE(resolveLayout(wall, 1), resolveLayout(wall, 2));
  EXPECT_NE(gpu::ComputeProgram(testContext(), "antialias.comp").layout(),
            gpu::ComputeProgram(testContext(), "dof_tiles.comp").layout());
  // A session's pipeline made after another's compiles nothing new: the first keeps them alive.
  FramePipeline first(testContext(), wall.scene, *wall.gpu, 32, 16);
  size_t made = testContext().sharedObjects();
  FramePipeline second(testContext(), dof.scene, *dof.gpu, 48, 16);
  EXPECT_EQ(testContext().sharedObjects(), made);
}

TEST(ComputeProgram, AShaderThatReadsTheSceneNeedsIt) {
  std::string error = errorOf([] { gpu::ComputeProgram(testContext(), "reference.comp"); });
  EXPECT_NE(error.find("reads the scene"), std::string::npos) << error;
}

}  // namespace
}  // namespace hdof::test
