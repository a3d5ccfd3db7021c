// The selective ray trace: only listed pixels are traced; hits split into near and far layers.
#include "render/frame_images.h"
#include "render/steps.h"
#include "render_fixture.h"

#include <gtest/gtest.h>
#include <shared/ray_work.h>

#include <cstring>

namespace hdof::test {
namespace {

constexpr uint32_t kWidth = 192, kHeight = 108;

struct TraceRig {
  SceneOnGpu& scene = testScene("builtin:dof");
  gpu::Buffer uniforms{testContext(), sizeof(gpu::FrameUniforms),
                       VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUse::Upload, "test uniforms"};
  gpu::Buffer workList{testContext(),
                       sizeof(gpu::RayWorkHeader) + kWidth* kHeight* gpu::kRayWorkEntrySize,
                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                       gpu::MemoryUse::Upload, "test work list"};
  FrameImages images{testContext(), kWidth, kHeight};
  const HybridImages& layers = images.hybrid;
  gpu::ComputeProgram program{testContext(), "hybrid_trace.comp", &scene.gpu->setLayout()};
  gpu::GpuTimer timer{testContext()};

  TraceRig() {
    Lens lens = onSceneCameraSensor(Lens{100.0f, 1.4f, *scene.scene.cameras.front().focusDistance},
                                    scene.scene.cameras.front(), kWidth, kHeight);
    FrameSettings settings{kWidth, kHeight};
    gpu::FrameUniforms u = makeFrameUniforms(
        scene.scene, Camera::fromScene(scene.scene.cameras.front()), lens, settings);
    std::memcpy(uniforms.mapped(), &u, sizeof(u));
  }

  // Lists every pixel with raysOf(x, y) > 0, with that many rays, and traces them from each
  // pixel's first sample.
  template <typename RaysOf>
  void trace(RaysOf raysOf) {
    auto* header = static_cast<gpu::RayWorkHeader*>(workList.mapped());
    auto* entries = reinterpret_cast<glm::uvec2*>(header + 1);
    uint32_t count = 0;
    for (uint32_t y = 0; y < kHeight; ++y)
      for (uint32_t x = 0; x < kWidth; ++x)
        if (uint32_t rays = raysOf(x, y)) entries[count++] = {gpu::packRayWorkPixel(x, y), rays};
    *header = {(count + gpu::kRayWorkGroupSize - 1) / gpu::kRayWorkGroupSize, 1, 1, count};
    testContext().submitAndWait([&](VkCommandBuffer cmd) {
      VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
      for (const gpu::Image* image :
           {&layers.nearLayer, &layers.farLayer, &layers.farPosition, &layers.layerCoc}) {
        VkClearColorValue sentinel{{-1.0f, -1.0f, -1.0f, -1.0f}};
        vkCmdClearColorImage(cmd, image->get(), VK_IMAGE_LAYOUT_GENERAL, &sentinel, 1, &range);
      }
      VkClearColorValue noSamples{};
      vkCmdClearColorImage(cmd, layers.samplesTraced.get(), VK_IMAGE_LAYOUT_GENERAL, &noSamples, 1,
                           &range);
      gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT);
      timer.reset(cmd);
      StepRecorder steps(cmd, timer, uniforms, *scene.gpu);
      steps.dispatch(program,
                     {{"workList", workList},
                      {"nearLayer", layers.nearLayer},
                      {"farLayer", layers.farLayer},
                      {"farPosition", layers.farPosition},
                      {"layerCoc", layers.layerCoc},
                      {"samplesTraced", layers.samplesTraced}},
                     gpu::Grid::indirect(workList));
    });
  }
};

TEST(HybridTrace, WritesOnlyListedPixelsAndSplitsNearFromFar) {
  TraceRig rig;
  rig.trace([](uint32_t, uint32_t y) { return y % 2 == 0 ? 64u : 0u; });
  std::vector<glm::vec4> nearLayer = readImage(rig.layers.nearLayer);
  std::vector<float> depth = renderDepth({"builtin:dof", "", RenderMode::Pinhole, kWidth, kHeight});
  int nearInterior = 0, farOpen = 0;
  for (uint32_t y = 0; y < kHeight; ++y)
    for (uint32_t x = 0; x < kWidth; ++x) {
      glm::vec4 n = nearLayer[y * kWidth + x];
      if (y % 2) {
        EXPECT_EQ(n.a, -1.0f) << "unlisted pixel " << x << "," << y << " was written";
        continue;
      }
      ASSERT_GE(n.a, 0.0f);
      ASSERT_LE(n.a, 1.0f);
      // Whole neighbourhoods at one depth: inside the railing (0.8 m) every ray is near; far
      // wall with nothing near in front of it, every ray is far.
      float lo = 1e9f, hi = 0.0f;
      for (int dy = -6; dy <= 6; ++dy)
        for (int dx = -6; dx <= 6; ++dx) {
          int px = std::clamp(int(x) + dx, 0, int(kWidth) - 1);
          int py = std::clamp(int(y) + dy, 0, int(kHeight) - 1);
          lo = std::min(lo, depth[py * kWidth + px]), hi = std::max(hi, depth[py * kWidth + px]);
        }
      if (hi < 1.0f) {
        EXPECT_GT(n.a, 0.95f) << x << "," << y;
        ++nearInterior;
      } else if (lo > 8.0f) {
        EXPECT_LT(n.a, 0.05f) << x << "," << y;
        ++farOpen;
      }
    }
  EXPECT_GT(nearInterior, 3);
  EXPECT_GT(farOpen, 10);
}

// A subgroup's lanes share out its pixels' rays: what a pixel's layers hold depends on its own
// rays only, not on how many its neighbours in the list ask for.
TEST(HybridTrace, APixelsLayersDoNotDependOnItsNeighboursRayCounts) {
  TraceRig rig;
  auto raysOf = [](uint32_t x, uint32_t y) { return (x * 7 + y * 3 + x / 5) % 5; };  // 0 to 4
  rig.trace(raysOf);
  std::vector<std::vector<glm::vec4>> mixed;
  for (const gpu::Image* image :
       {&rig.layers.nearLayer, &rig.layers.farLayer, &rig.layers.farPosition, &rig.layers.layerCoc})
    mixed.push_back(readImage(*image));
  int compared = 0;
  for (uint32_t rays = 1; rays <= 4; ++rays) {
    rig.trace([&](uint32_t x, uint32_t y) { return raysOf(x, y) == rays ? rays : 0u; });
    size_t layer = 0;
    for (const gpu::Image* image : {&rig.layers.nearLayer, &rig.layers.farLayer,
                                    &rig.layers.farPosition, &rig.layers.layerCoc}) {
      std::vector<glm::vec4> alone = readImage(*image);
      for (uint32_t y = 0; y < kHeight; ++y)
        for (uint32_t x = 0; x < kWidth; ++x) {
          if (raysOf(x, y) != rays) continue;
          size_t i = size_t(y) * kWidth + x;
          for (int c = 0; c < 4; ++c)
            ASSERT_NEAR(mixed[layer][i][c], alone[i][c], 1e-3f * (1.0f + std::abs(alone[i][c])))
                << "layer " << layer << " channel " << c << " at " << x << "," << y << " (" << rays
                << " rays)";
          ++compared;
        }
      ++layer;
    }
  }
  int listed = 0;
  for (uint32_t y = 0; y < kHeight; ++y)
    for (uint32_t x = 0; x < kWidth; ++x) listed += raysOf(x, y) > 0;
  EXPECT_EQ(compared, 4 * listed);
  EXPECT_GT(listed, int(kWidth * kHeight / 2));
}

}  // namespace
}  // namespace hdof::test
