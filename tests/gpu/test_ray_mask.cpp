// The adaptive ray mask: nothing on an in-focus wall; rays by the variance of a pixel's rays, out
// of focus by its noisiest neighbour's too; at rest, trusted quiet pixels in turns; on the
// depth-of-field scene, rays along the blurred foreground's silhouettes only, fewer as the
// aperture closes, fewer per pixel where both sides of an edge are blurred (rays by CoC); the
// work list holds exactly the pixels with rays, with dispatch arguments for them.
#include "render/gbuffer_pass.h"
#include "render/ray_mask.h"
#include "render_fixture.h"

#include <gtest/gtest.h>

#include <shared/dof.h>
#include <shared/ray_work.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <set>

namespace hdof::test {
namespace {

constexpr uint32_t kSamplesPerPixel = 4;

// The G-buffer and the ray mask recorded by hand (so that a test can give the mask its own
// variance), with depth, rays and the work list read back.
class RayMaskRig {
 public:
  RayMaskRig(const std::string& sceneSpec, uint32_t width, uint32_t height)
      : scene_(testScene(sceneSpec)),
        images_(testContext(), width, height),
        gbuffer_(testContext(), scene_.scene, *scene_.gpu),
        mask_(testContext()),
        uniformBuffer_(testContext(), sizeof(gpu::FrameUniforms),
                       VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUse::Upload, "test uniforms"),
        listReadback_(testContext(), images_.mask.workList.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                      gpu::MemoryUse::Readback, "test work list"),
        timer_(testContext()) {
    gbuffer_.bindImages(images_.gbuffer, width, height);
    camera_ = Camera::fromScene(scene_.scene.cameras.front());
    suggestedFocus_ = scene_.scene.cameras.front().focusDistance.value_or(5.0f);
  }

  struct Frame {
    std::vector<float> depth;
    std::vector<glm::vec3> normals;
    std::vector<uint8_t> rays;
    gpu::RayWorkHeader header{};
    std::vector<glm::uvec2> entries;
    uint32_t listedPixels = 0;
    double coverage = 0.0;
    std::vector<std::pair<std::string, double>> passMs;
  };

  // lens.focusDistance 0: the scene camera's suggestion. rasterSample > 0: a resting view's;
  // stillFrames: how long camera and lens have rested.
  Frame render(Lens lens, const gpu::Image* variance = nullptr, uint32_t rasterSample = 0,
               uint32_t stillFrames = 0, RayMaskOptions options = {}) {
    gpu::FrameUniforms uniforms = uniformsFor(lens);
    uniforms.stillFrames = stillFrames;
    // A resting view's raster has its first sample (the pixel centre's depth and normals) before
    // the later ones, as in the frame pipeline.
    for (uint32_t sample : std::set<uint32_t>{0u, rasterSample}) {
      uniforms.rasterSample = sample;
      std::memcpy(uniformBuffer_.mapped(), &uniforms, sizeof(uniforms));
      testContext().submitAndWait([&](VkCommandBuffer cmd) {
        timer_.reset(cmd);
        StepRecorder steps(cmd, timer_, uniformBuffer_, *scene_.gpu);
        gbuffer_.record(steps, images_.gbuffer, uniforms, sample > 0);
      });
    }
    testContext().submitAndWait([&](VkCommandBuffer cmd) {
      timer_.reset(cmd);
      StepRecorder steps(cmd, timer_, uniformBuffer_, *scene_.gpu);
      mask_.record(steps, images_.gbuffer, images_.mask, variance, options);
    });
    Frame frame;
    frame.passMs = timer_.results();
    gpu::RayWorkHeader listed = readWorkHeader(images_.mask);
    frame.listedPixels = listed.count;
    frame.coverage = double(listed.count) / double(pixelCount());
    testContext().submitAndWait([&](VkCommandBuffer cmd) {
      gpu::copyBufferToHost(cmd, images_.mask.workList, listReadback_, listReadback_.size());
    });
    for (const glm::vec4& texel : readImage(images_.gbuffer.normalDepth)) {
      frame.depth.push_back(texel.w);
      frame.normals.push_back(glm::vec3(texel));
    }
    frame.rays = readBytes(images_.mask.rays);
    const auto* list = static_cast<const std::byte*>(listReadback_.mapped());
    std::memcpy(&frame.header, list, sizeof(frame.header));
    frame.entries.resize(frame.header.count);
    std::memcpy(frame.entries.data(), list + sizeof(gpu::RayWorkHeader),
                frame.entries.size() * sizeof(glm::uvec2));
    return frame;
  }

  // The frame uniforms render() uses for `lens`.
  gpu::FrameUniforms uniformsFor(Lens lens) const {
    if (lens.focusDistance <= 0.0f) lens.focusDistance = suggestedFocus_;
    FrameSettings settings;
    settings.width = width();
    settings.height = height();
    lens = onSceneCameraSensor(lens, scene_.scene.cameras.front(), width(), height());
    settings.samplesPerPixel = kSamplesPerPixel;
    return makeFrameUniforms(scene_.scene, camera_, lens, settings);
  }

  uint32_t width() const { return images_.width; }
  uint32_t height() const { return images_.height; }

 private:
  size_t pixelCount() const { return size_t(width()) * height(); }

  static std::vector<uint8_t> readBytes(const gpu::Image& image) {
    gpu::Buffer buffer(testContext(), VkDeviceSize(image.width()) * image.height(),
                       VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUse::Readback, "test bytes");
    testContext().submitAndWait(
        [&](VkCommandBuffer cmd) { gpu::copyImageToBuffer(cmd, image, buffer); });
    const auto* bytes = static_cast<const uint8_t*>(buffer.mapped());
    return std::vector<uint8_t>(bytes, bytes + buffer.size());
  }

  SceneOnGpu& scene_;
  FrameImages images_;
  GBufferPass gbuffer_;
  RayMask mask_;
  gpu::Buffer uniformBuffer_;
  gpu::Buffer listReadback_;
  gpu::GpuTimer timer_;
  Camera camera_;
  float suggestedFocus_ = 5.0f;
};

constexpr uint32_t kWidth = 640, kHeight = 360;
const Lens kWideOpen{50.0f, 1.4f, 0.0f};

size_t pixelsWithRays(const RayMaskRig::Frame& frame) {
  return std::count_if(frame.rays.begin(), frame.rays.end(), [](uint8_t r) { return r > 0; });
}

// The work list holds each pixel with rays once, with its ray count, and its dispatch covers it.
void expectListMatchesMask(const RayMaskRig::Frame& frame, uint32_t width) {
  EXPECT_EQ(frame.header.count, pixelsWithRays(frame));
  EXPECT_EQ(frame.listedPixels, frame.header.count);
  EXPECT_EQ(frame.header.groupsX,
            (frame.header.count + gpu::kRayWorkGroupSize - 1) / gpu::kRayWorkGroupSize);
  EXPECT_EQ(frame.header.groupsY, 1u);
  EXPECT_EQ(frame.header.groupsZ, 1u);
  std::set<uint32_t> seen;
  for (const glm::uvec2& entry : frame.entries) {
    glm::uvec2 pixel = gpu::unpackRayWorkPixel(entry.x);
    EXPECT_TRUE(seen.insert(entry.x).second) << "listed twice: " << pixel.x << ", " << pixel.y;
    EXPECT_EQ(entry.y, frame.rays[pixel.y * width + pixel.x]);
  }
  for (uint8_t rays : frame.rays) EXPECT_LE(rays, kSamplesPerPixel);
}

// A variance image as hybrid_temporal.comp writes it (rg: one ray's variance, rays accumulated),
// every pixel alike.
class FlatVariance {
 public:
  FlatVariance(uint32_t width, uint32_t height)
      : batch_(testContext()),
        image_(batch_.make(width, height, VK_FORMAT_R32G32_SFLOAT, "test variance")) {
    batch_.finish();
  }
  const gpu::Image* set(float variance, float raysAccumulated) {
    testContext().submitAndWait([&](VkCommandBuffer cmd) {
      VkClearColorValue value{{variance, raysAccumulated, 0.0f, 0.0f}};
      VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
      vkCmdClearColorImage(cmd, image_.get(), VK_IMAGE_LAYOUT_GENERAL, &value, 1, &range);
    });
    return &image_;
  }

 private:
  gpu::ImageBatch batch_;
  gpu::Image image_;
};

TEST(RayMask, InFocusWallNeedsNoRays) {
  RayMaskRig rig("builtin:wall", 321, 181);
  RayMaskRig::Frame frame = rig.render(Lens{50.0f, 1.4f, 3.0f});
  EXPECT_EQ(frame.coverage, 0.0);
  EXPECT_EQ(frame.header.count, 0u);
  EXPECT_EQ(pixelsWithRays(frame), 0u);
  expectListMatchesMask(frame, rig.width());
}

// Pixels get rays by the variance of their rays. Once camera and lens have rested as many frames
// as the raster takes samples (no G-buffer work any more), a pixel whose traced colour the
// composite already shows alone gets the full rays; one with fewer rays keeps its variance's.
TEST(RayMask, NoisyPixelsGetRaysByTheirVarianceAndTrustedOnesAllAtRest) {
  constexpr uint32_t kW = 64, kH = 48;
  RayMaskRig rig("builtin:wall", kW, kH);
  FlatVariance flat(kW, kH);
  // Halfway between the variance that turns rays on and the one that asks for all of them.
  const float noise = 0.5f * gpu::kRayMaskVarianceFull;
  const Lens lens{50.0f, 1.4f, 3.0f};
  const gpu::Image* variance = flat.set(noise, gpu::kHybridTrustedRays);
  RayMaskRig::Frame frame = rig.render(lens, variance, 1, gpu::kStillRasterFrames - 1);
  EXPECT_EQ(frame.coverage, 1.0);
  for (uint8_t rays : frame.rays) ASSERT_EQ(rays, kSamplesPerPixel / 2);
  expectListMatchesMask(frame, rig.width());
  RayMaskRig::Frame resting = rig.render(lens, variance, 1, gpu::kStillRasterFrames);
  EXPECT_EQ(resting.coverage, 1.0);
  for (uint8_t rays : resting.rays) ASSERT_EQ(rays, kSamplesPerPixel);
  variance = flat.set(noise, gpu::kHybridTrustedRays - 1.0f);
  RayMaskRig::Frame untrusted = rig.render(lens, variance, 1, gpu::kStillRasterFrames);
  for (uint8_t rays : untrusted.rays) ASSERT_EQ(rays, kSamplesPerPixel / 2);
}

// At rest, a quiet pixel that the composite shows as traced alone takes its rays in turns when
// the frame allows it: four rays every fourth frame, by 8x8 tiles, one tile of each 2x2 tiles a
// frame, every pixel once in four frames. Others, and every pixel when turns are not allowed,
// get a ray a frame.
TEST(RayMask, TrustedQuietPixelsAtRestTakeTheirRaysInTurns) {
  constexpr uint32_t kW = 64, kH = 48;
  RayMaskRig rig("builtin:wall", kW, kH);
  FlatVariance flat(kW, kH);
  const Lens lens{50.0f, 1.4f, 3.0f};
  const RayMaskOptions inTurns{.inTurns = true};
  const gpu::Image* variance = flat.set(0.0f, gpu::kHybridTrustedRays);
  std::vector<int> timesListed(kW * kH, 0);
  for (uint32_t turn = 0; turn < 4; ++turn) {
    RayMaskRig::Frame frame =
        rig.render(lens, variance, 1, gpu::kStillRasterFrames + turn, inTurns);
    for (uint8_t rays : frame.rays) ASSERT_EQ(rays, 4u);
    EXPECT_EQ(frame.header.count, kW * kH / 4);
    EXPECT_EQ(frame.header.rays, kW * kH);
    std::vector<int> perTile(kW * kH / 64, 0), perBlock(kW * kH / 256, 0);
    for (const glm::uvec2& entry : frame.entries) {
      glm::uvec2 pixel = gpu::unpackRayWorkPixel(entry.x);
      EXPECT_EQ(entry.y, 4u);
      ++timesListed[pixel.y * kW + pixel.x];
      ++perTile[pixel.y / 8 * (kW / 8) + pixel.x / 8];
      ++perBlock[pixel.y / 16 * (kW / 16) + pixel.x / 16];
    }
    for (int listed : perTile) ASSERT_TRUE(listed == 0 || listed == 64) << listed;
    for (int listed : perBlock) ASSERT_EQ(listed, 64);
  }
  for (int listed : timesListed) ASSERT_EQ(listed, 1);
  // Not allowed, or not trusted yet: a ray a frame, every pixel listed.
  RayMaskRig::Frame everyFrame = rig.render(lens, variance, 1, gpu::kStillRasterFrames);
  for (uint8_t rays : everyFrame.rays) ASSERT_EQ(rays, 1u);
  expectListMatchesMask(everyFrame, rig.width());
  variance = flat.set(0.0f, gpu::kHybridTrustedRays - 1.0f);
  RayMaskRig::Frame young = rig.render(lens, variance, 1, gpu::kStillRasterFrames, inTurns);
  for (uint8_t rays : young.rays) ASSERT_EQ(rays, 1u);
  expectListMatchesMask(young, rig.width());
}

// On a still view out of focus, a settled pixel counts as noisy as its noisiest settled neighbour:
// beside a light's blur, rays that have not met the light yet read no variance. In focus, and in
// motion, its own variance counts.
TEST(RayMask, BlurredPixelsBesideANoisyOneGetItsRays) {
  constexpr uint32_t kW = 64, kH = 48;
  constexpr glm::ivec2 kNoisy{20, 20};
  RayMaskRig rig("builtin:wall", kW, kH);
  gpu::ImageBatch batch(testContext());
  gpu::Image variance = batch.make(kW, kH, VK_FORMAT_R32G32_SFLOAT, "test variance");
  batch.finish();
  // Every pixel settled (8 rays) with no variance at all (its rays all saw the same colour); one
  // whose rays met a light of luminance 30 half the time.
  gpu::Buffer upload(testContext(), VkDeviceSize(kW) * kH * sizeof(glm::vec2),
                     VK_BUFFER_USAGE_TRANSFER_SRC_BIT, gpu::MemoryUse::Upload, "test upload");
  auto* texels = static_cast<glm::vec2*>(upload.mapped());
  std::fill(texels, texels + kW * kH, glm::vec2(0.0f, 8.0f));
  texels[kNoisy.y * kW + kNoisy.x] = glm::vec2(0.25f * 30.0f * 30.0f, 8.0f);
  testContext().submitAndWait([&](VkCommandBuffer cmd) {
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {kW, kH, 1};
    vkCmdCopyBufferToImage(cmd, upload.get(), variance.get(), VK_IMAGE_LAYOUT_GENERAL, 1, &region);
  });
  auto raysAt = [&](const RayMaskRig::Frame& frame, glm::ivec2 p) {
    return frame.rays[p.y * kW + p.x];
  };

  // The wall is 3 m away: focused at 0.5 m it is a blur of about 6 px.
  const Lens blurring{50.0f, 1.4f, 0.5f};
  RayMaskRig::Frame blurred = rig.render(blurring, &variance, 0, 1);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      EXPECT_EQ(raysAt(blurred, kNoisy + glm::ivec2(dx, dy)), kSamplesPerPixel) << dx << ", " << dy;
  EXPECT_EQ(pixelsWithRays(blurred), 9u);
  expectListMatchesMask(blurred, kW);

  RayMaskRig::Frame moving = rig.render(blurring, &variance, 0, 0);
  EXPECT_EQ(raysAt(moving, kNoisy), kSamplesPerPixel);
  EXPECT_EQ(pixelsWithRays(moving), 1u);
  RayMaskRig::Frame sharp = rig.render(Lens{50.0f, 1.4f, 3.0f}, &variance, 0, 1);
  EXPECT_EQ(raysAt(sharp, kNoisy), kSamplesPerPixel);
  EXPECT_EQ(pixelsWithRays(sharp), 1u);
}

TEST(RayMask, CoversTheBlurredRailingsSilhouette) {
  RayMaskRig rig("builtin:dof", kWidth, kHeight);
  RayMaskRig::Frame frame = rig.render(kWideOpen);
  // The railing at 0.8 m where the background (beyond 2 m) is next to it.
  size_t silhouette = 0, covered = 0;
  for (uint32_t y = 1; y + 1 < kHeight; ++y) {
    for (uint32_t x = 1; x + 1 < kWidth; ++x) {
      size_t i = size_t(y) * kWidth + x;
      if (frame.depth[i] >= 1.0f) continue;
      bool nextToBackground = false;
      for (size_t j : {i - 1, i + 1, i - kWidth, i + kWidth})
        nextToBackground = nextToBackground || frame.depth[j] > 2.0f;
      if (!nextToBackground) continue;
      ++silhouette;
      covered += frame.rays[i] > 0;
    }
  }
  ASSERT_GT(silhouette, 100u);
  EXPECT_GE(double(covered) / double(silhouette), 0.9);
  EXPECT_GT(frame.coverage, 0.0);
  EXPECT_LT(frame.coverage, 0.3);
  expectListMatchesMask(frame, rig.width());
  std::printf("builtin:dof f/1.4: coverage %.3f, railing silhouette covered %zu of %zu\n",
              frame.coverage, covered, silhouette);
}

TEST(RayMask, ClosingTheApertureNeedsFewerRays) {
  RayMaskRig rig("builtin:dof", kWidth, kHeight);
  RayMaskRig::Frame wide = rig.render(kWideOpen);
  RayMaskRig::Frame narrow = rig.render(Lens{50.0f, 8.0f, 0.0f});
  EXPECT_LT(narrow.coverage, 0.5 * wide.coverage);
  expectListMatchesMask(narrow, rig.width());
  std::printf("builtin:dof coverage: f/1.4 %.3f, f/8 %.3f\n", wide.coverage, narrow.coverage);
}

// Rays by CoC: focused at 0.3 m, every edge of the scene is blurred on both sides by far more than
// kRayMaskDenseCoc, so its pixels get a quarter of the rays or fewer; at the scene's focus the
// sharp-backed silhouettes keep the full rays.
TEST(RayMask, EdgesBlurredOnBothSidesGetFewerRays) {
  RayMaskRig rig("builtin:dof", kWidth, kHeight);
  RayMaskRig::Frame allBlurred = rig.render(Lens{50.0f, 1.4f, 0.3f});
  ASSERT_GT(pixelsWithRays(allBlurred), 0u);
  EXPECT_EQ(*std::max_element(allBlurred.rays.begin(), allBlurred.rays.end()),
            (kSamplesPerPixel + 3) / 4);
  expectListMatchesMask(allBlurred, rig.width());
  RayMaskRig::Frame focused = rig.render(kWideOpen);
  EXPECT_EQ(*std::max_element(focused.rays.begin(), focused.rays.end()), kSamplesPerPixel);
}

// ... but only where the spatial reconstruction fills in: focused in front of the whole scene,
// every pixel's CoC lies between 0.9 and 1 times a 6.5 px blur (A f (1/S - 1/z) with S a tenth
// of the nearest depth), under kRayMaskDenseCoc, so the strongest edges keep the full rays.
TEST(RayMask, BlursTheReconstructionDoesNotReachKeepTheFullRays) {
  RayMaskRig rig("builtin:dof", kWidth, kHeight);
  RayMaskRig::Frame view = rig.render(kWideOpen);
  float nearest = *std::min_element(view.depth.begin(), view.depth.end());
  ASSERT_GT(nearest, 0.0f);
  constexpr float kBlur = 6.5f;
  ASSERT_LT(kBlur, gpu::kRayMaskDenseCoc);
  ASSERT_GT(0.9f * kBlur, gpu::kDofFocusZone);
  Lens lens{50.0f, 1.0f, 0.1f * nearest};
  gpu::FrameUniforms atF1 = rig.uniformsFor(lens);
  lens.fNumber = atF1.apertureDiameter * atF1.focalLengthPixels / (lens.focusDistance * kBlur);
  gpu::FrameUniforms uniforms = rig.uniformsFor(lens);
  for (float depth : view.depth) {
    float coc = gpu::signedCocPixels(depth, uniforms.apertureDiameter, uniforms.focusDistance,
                                     uniforms.focalLengthPixels);
    ASSERT_GE(coc, 0.89f * kBlur);
    ASSERT_LE(coc, 1.01f * kBlur);
  }
  RayMaskRig::Frame blurred = rig.render(lens);
  ASSERT_GT(pixelsWithRays(blurred), 0u);
  EXPECT_EQ(*std::max_element(blurred.rays.begin(), blurred.rays.end()), kSamplesPerPixel);
}

// A resting view also traces the pixels that an in-focus edge crosses (the raster's samples fall
// short of the traced image's antialiasing there), and those alone: a depth or normal step lies
// within the 3x3 of every one. A moving view (no raster samples yet) traces none of them, nor
// does a focus pull's frame (the raster stands, the lens just changed).
TEST(RayMask, ARestingViewTracesThePixelsInFocusEdgesCross) {
  RayMaskRig rig("builtin:dof", 320, 180);
  const Lens pinhole{50.0f, 1e6f, 0.0f};
  EXPECT_EQ(rig.render(pinhole).header.count, 0u) << "nothing is blurred";
  EXPECT_EQ(rig.render(pinhole, nullptr, 1, 0).header.count, 0u) << "the lens just changed";
  RayMaskRig::Frame resting = rig.render(pinhole, nullptr, 1, 1);
  expectListMatchesMask(resting, rig.width());
  std::printf("edge pixels traced at rest: %.1f%% of the image\n", 100.0 * resting.coverage);
  EXPECT_GT(resting.coverage, 0.01);
  EXPECT_LT(resting.coverage, 0.3);
  int w = int(rig.width()), h = int(rig.height());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (resting.rays[y * w + x] == 0) continue;
      float nearest = 1e30f, farthest = 0.0f, agreement = 1.0f;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          int q = std::clamp(y + dy, 0, h - 1) * w + std::clamp(x + dx, 0, w - 1);
          nearest = std::min(nearest, resting.depth[q]);
          farthest = std::max(farthest, resting.depth[q]);
          agreement = std::min(agreement, glm::dot(resting.normals[q], resting.normals[y * w + x]));
        }
      // The shader's test on inverse depths, 1 / nearest > (1 + low) / farthest, with a margin.
      bool step = farthest > nearest * (1.0f + 0.9f * gpu::kRayMaskDepthJumpLow) ||
                  agreement < gpu::kRayMaskCrossedNormal + 0.01f;
      ASSERT_TRUE(step) << "no edge crosses traced pixel " << x << ", " << y;
    }
}

// Not a test of speed (that is for benchmarks): prints each pass's GPU time at 640x360.
TEST(RayMask, ReportsEveryPassTime) {
  RayMaskRig rig("builtin:dof", kWidth, kHeight);
  constexpr int kFrames = 10;
  std::vector<std::pair<std::string, std::vector<double>>> times;  // in recording order
  for (int frame = 0; frame <= kFrames; ++frame) {
    RayMaskRig::Frame result = rig.render(kWideOpen);
    if (frame == 0) continue;  // shader compilation
    times.resize(result.passMs.size());
    for (size_t i = 0; i < result.passMs.size(); ++i) {
      times[i].first = result.passMs[i].first;
      times[i].second.push_back(result.passMs[i].second);
    }
  }
  // clear, edges, tiles, dilate, far rows and columns, spread, columns, rays, indirect, readback
  EXPECT_EQ(times.size(), 11u);
  double total = 0.0;
  std::printf("builtin:dof %ux%u f/1.4, median of %d frames:\n", kWidth, kHeight, kFrames);
  for (auto& [name, ms] : times) {
    std::sort(ms.begin(), ms.end());
    total += ms[ms.size() / 2];
    std::printf("  %-18s %6.2f ms\n", name.c_str(), ms[ms.size() / 2]);
  }
  std::printf("  %-18s %6.2f ms\n", "sum", total);
}

}  // namespace
}  // namespace hdof::test
