// Temporal accumulation of the hybrid's ray-traced layers: history grows while the view rests,
// the variance that drives the ray mask settles, and a cut starts over; the spatial
// reconstruction after it.
#include "quality/occlusion_mask.h"
#include "render_fixture.h"

#include <gtest/gtest.h>
#include <shared/dof.h>

#include <algorithm>
#include <cstring>
#include <optional>

namespace hdof::test {
namespace {

constexpr uint32_t kWidth = 160, kHeight = 90, kRaysPerPixel = 4;

// Hybrid frames of a still view, with the temporal history read back.
struct TemporalRig {
  SceneOnGpu& scene = testScene("builtin:dof");
  FramePipeline pipeline{testContext(), scene.scene, *scene.gpu, kWidth, kHeight};
  uint32_t frame = 0;
  float fNumber = 1.4f;

  // focusScale: the focus distance over the scene camera's (a lens change when it differs from
  // the previous frame's); shift: metres the camera moves to its right.
  void render(bool cut, float focusScale = 1.0f, float shift = 0.0f) {
    FrameRequest request;
    request.mode = RenderMode::Hybrid;
    request.camera = Camera::fromScene(scene.scene.cameras.front());
    request.camera.position +=
        shift * glm::normalize(glm::cross(request.camera.forward, request.camera.up));
    request.lens = onSceneCameraSensor(
        Lens{50.0f, fNumber, *scene.scene.cameras.front().focusDistance * focusScale},
        scene.scene.cameras.front(), kWidth, kHeight);
    request.settings = {kWidth, kHeight, frame, kRaysPerPixel};
    if (cut) pipeline.resetHistory();
    pipeline.render(request);
    ++frame;
  }
  const HybridImages::History& history() const { return pipeline.hybridHistory(); }
  const gpu::Image& variance() const { return pipeline.images().hybrid.variance; }
};

TEST(HybridTemporal, HistoryGrowsWhileStillAndACutStartsOver) {
  TemporalRig rig;
  for (int i = 0; i < 3; ++i) rig.render(false);
  std::vector<glm::vec4> moments = readImage(rig.history().moments);
  // The history counts rays: 1 to kRaysPerPixel a frame.
  int traced = 0, allAlong = 0;
  for (const glm::vec4& m : moments) {
    if (m.z == 0.0f) continue;
    ++traced;
    EXPECT_LE(m.z, 3.0f * kRaysPerPixel);
    allAlong += m.z >= 3.0f;
  }
  EXPECT_GT(allAlong, traced / 2) << "most traced pixels stayed in the mask";
  EXPECT_GT(traced, int(kWidth * kHeight / 20)) << "the mask traced something";

  for (int i = 0; i < 9; ++i) rig.render(false);
  moments = readImage(rig.history().moments);
  int settled = 0, counted = 0;
  std::vector<float> variances;
  {
    // rg16f: the variance of one ray, the rays accumulated.
    gpu::Buffer buffer(testContext(), kWidth * kHeight * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                       gpu::MemoryUse::Readback, "variance");
    testContext().submitAndWait(
        [&](VkCommandBuffer cmd) { gpu::copyImageToBuffer(cmd, rig.variance(), buffer); });
    const auto* pairs = static_cast<const uint32_t*>(buffer.mapped());
    for (size_t i = 0; i < size_t(kWidth) * kHeight; ++i) {
      glm::vec2 pair = glm::unpackHalf2x16(pairs[i]);
      variances.push_back(pair.x);
      if (moments[i].z > 0.0f) {
        EXPECT_EQ(pair.y, moments[i].z) << "the rays accumulated";
      }
    }
  }
  for (size_t i = 0; i < moments.size(); ++i) {
    if (moments[i].z < 12.0f) continue;  // pixels the mask kept (at least a ray a frame)
    ++counted;
    settled += variances[i] < 0.5f;
  }
  ASSERT_GT(counted, 0);
  EXPECT_GT(settled, counted * 3 / 4) << "twelve frames in, most traced pixels are settled";

  rig.render(true);
  moments = readImage(rig.history().moments);
  for (const glm::vec4& m : moments) {
    if (m.z > 0.0f) {
      ASSERT_LE(m.z, float(kRaysPerPixel)) << "a cut drops the history";
    }
  }
}

// A pixel the mask leaves out drops its history: after a focus change moves the mask, every pixel
// without rays this frame has no moments and no variance, pixels that had a history in that set
// two frames before among them.
TEST(HybridTemporal, APixelTheMaskLeavesOutDropsItsHistory) {
  TemporalRig rig;
  for (int i = 0; i < 3; ++i) rig.render(i == 0);
  std::vector<glm::vec4> twoFramesBefore = readImage(rig.history().moments);
  rig.render(false);
  rig.render(false, 0.5f);
  std::vector<glm::vec4> rays = readImage(rig.pipeline.images().mask.rays);
  std::vector<glm::vec4> moments = readImage(rig.history().moments);
  std::vector<glm::vec4> variance = readImage(rig.variance());
  int leftOut = 0, dropped = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (rays[i].x > 0.0f) {
      ASSERT_GT(moments[i].z, 0.0f) << "a traced pixel counts its rays";
      continue;
    }
    ++leftOut;
    dropped += twoFramesBefore[i].z > 0.0f;
    ASSERT_EQ(moments[i].z, 0.0f) << "pixel " << i << " was left out";
    ASSERT_EQ(variance[i], glm::vec4(0.0f)) << "pixel " << i << " was left out";
  }
  EXPECT_GT(leftOut, int(kWidth * kHeight / 4));
  EXPECT_GT(dropped, 100) << "the focus change left out pixels that had a history";
}

// The moving average's window: ten frames' rays after a change, growing by a frame per still
// frame (so that a resting view keeps converging), and short again once the lens changes.
TEST(HybridTemporal, WindowGrowsWhileStillAndShrinksOnALensChange) {
  TemporalRig rig;
  constexpr float kChangeWindowRays = 10.0f * kRaysPerPixel;
  auto longestHistory = [&] {
    float longest = 0.0f;
    for (const glm::vec4& m : readImage(rig.history().moments)) longest = std::max(longest, m.z);
    return longest;
  };
  for (int i = 0; i < 24; ++i) rig.render(i == 0);
  EXPECT_GT(longestHistory(), 1.5f * kChangeWindowRays) << "a still view averages past ten frames";
  rig.render(false, 1.1f);
  EXPECT_LE(longestHistory(), kChangeWindowRays) << "a focus change shortens the window";
  // A camera move so small that the background hardly moves on screen: a near silhouette's blur
  // moves with its own parallax, so every traced pixel takes the short window of motion.
  for (int i = 0; i < 12; ++i) rig.render(false, 1.1f);
  rig.render(false, 1.1f, 0.002f);
  EXPECT_LE(longestHistory(), 2.5f * kRaysPerPixel) << "in motion the window is short everywhere";
}

// Pixels whose accumulated near layer lies outside the range of this frame's rays over their 3x3
// neighbourhood (the traced pixels', premultiplied by their hit ratio, as the history is).
int historyOutsideThisFramesRays(const TemporalRig& rig) {
  const FrameImages& images = rig.pipeline.images();
  std::vector<glm::vec4> now = readImage(images.hybrid.nearLayer);
  std::vector<glm::vec4> history = readImage(rig.history().nearLayer);
  std::vector<uint8_t> rays(size_t(kWidth) * kHeight);
  gpu::Buffer buffer(testContext(), rays.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                     gpu::MemoryUse::Readback, "rays");
  testContext().submitAndWait(
      [&](VkCommandBuffer cmd) { gpu::copyImageToBuffer(cmd, images.mask.rays, buffer); });
  std::memcpy(rays.data(), buffer.mapped(), rays.size());
  int outside = 0;
  for (int y = 0; y < int(kHeight); ++y)
    for (int x = 0; x < int(kWidth); ++x) {
      if (rays[size_t(y) * kWidth + x] == 0) continue;
      glm::vec4 low(1e30f), high(-1e30f);
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          size_t q = size_t(std::clamp(y + dy, 0, int(kHeight) - 1)) * kWidth +
                     size_t(std::clamp(x + dx, 0, int(kWidth) - 1));
          if (rays[q] == 0) continue;
          glm::vec4 premultiplied(glm::vec3(now[q]) * now[q].a, now[q].a);
          low = glm::min(low, premultiplied);
          high = glm::max(high, premultiplied);
        }
      glm::vec4 value = history[size_t(y) * kWidth + x];
      glm::vec4 tolerance = 2e-3f + 2e-3f * glm::abs(value);  // half-float rounding
      outside += glm::any(glm::lessThan(value, low - tolerance)) ||
                 glm::any(glm::greaterThan(value, high + tolerance));
    }
  return outside;
}

// A frame whose lens (or camera) changed clamps the history to what this frame's rays around a
// pixel saw, as TAA does, so that no stale layer lingers; a resting view's history averages its
// rays unclamped (below the noise of a frame's own, so some pixels lie outside that range).
TEST(HybridTemporal, AChangeClampsTheHistoryToThisFramesRays) {
  TemporalRig rig;
  for (int i = 0; i < 12; ++i) rig.render(false);
  EXPECT_GT(historyOutsideThisFramesRays(rig), 0);
  rig.render(false, 1.02f);
  EXPECT_EQ(historyOutsideThisFramesRays(rig), 0);
  for (int i = 0; i < 3; ++i) rig.render(false, 1.02f);
  EXPECT_GT(historyOutsideThisFramesRays(rig), 0) << "resting again";
  rig.render(false, 1.02f, 0.05f);
  EXPECT_EQ(historyOutsideThisFramesRays(rig), 0) << "the camera moved";
}

// The traced colour is already the lens's blur, so the spatial reconstruction gathers over an
// eighth of a pixel's CoC, not over the blur itself (which blurred it twice): a traced pixel
// whose blur is under 8 px keeps its accumulated colour; wider ones still borrow from their
// neighbours.
// Two frames of a wide-aperture still view (its pixels' histories still short) and, per traced
// pixel, the blur its spatial reconstruction reads (hybrid_spatial.comp): its layers' CoCs
// weighted by its hit ratio, and while its history is short, no less than the widest near CoC
// that its 3x3 neighbourhood's rays met times the share of their rays that met it.
struct SpatialFrame {
  struct Pixel {
    float blur, ownBlur;
    bool changed;  // the reconstruction differs from the history
  };
  std::vector<Pixel> traced;

  SpatialFrame() {
    TemporalRig rig;
    rig.fNumber = 0.5f;  // blurs from a pixel to tens of them at 160x90
    for (int i = 0; i < 2; ++i) rig.render(false);
    std::vector<glm::vec4> moments = readImage(rig.history().moments);
    std::vector<glm::vec4> history = readImage(rig.history().nearLayer);
    std::vector<glm::vec4> reconstructed =
        readImage(rig.pipeline.images().hybrid.reconstructedNear);
    std::vector<glm::vec4> coc = readImage(rig.pipeline.images().hybrid.layerCoc);
    std::vector<glm::vec4> variance = readImage(rig.variance());
    auto at = [](int x, int y) { return size_t(y) * kWidth + size_t(x); };
    for (int y = 0; y < int(kHeight); ++y) {
      for (int x = 0; x < int(kWidth); ++x) {
        size_t i = at(x, y);
        if (moments[i].z == 0.0f) continue;  // not traced this frame
        Pixel pixel{};
        pixel.ownBlur = glm::mix(std::abs(coc[i].y), coc[i].x, history[i].a);
        pixel.blur = pixel.ownBlur;
        if (variance[i].x >= gpu::kRayMaskVarianceNew) {
          float widest = 0.0f, ratioSum = 0.0f, count = 0.0f;
          for (int k = 0; k < 9; ++k) {
            size_t j = at(std::clamp(x + k % 3 - 1, 0, int(kWidth) - 1),
                          std::clamp(y + k / 3 - 1, 0, int(kHeight) - 1));
            if (moments[j].z == 0.0f) continue;
            widest = std::max(widest, coc[j].x);
            ratioSum += history[j].a;
            count += 1.0f;
          }
          pixel.blur = std::max(pixel.blur, widest * ratioSum / std::max(count, 1.0f));
        }
        // The history is single floats, the reconstruction half floats (rounded either way).
        glm::vec4 halfStep = glm::abs(history[i]) / 1024.0f + 1e-7f;
        pixel.changed =
            !glm::all(glm::lessThanEqual(glm::abs(reconstructed[i] - history[i]), halfStep));
        traced.push_back(pixel);
      }
    }
  }
};

TEST(HybridSpatial, GathersOverAnEighthOfTheBlur) {
  SpatialFrame frame;
  int kept = 0, narrow = 0, borrowed = 0, wide = 0;
  for (const SpatialFrame::Pixel& pixel : frame.traced) {
    if (pixel.blur < 7.5f) {
      ++narrow;
      kept += !pixel.changed;
    } else if (pixel.blur > 9.0f) {
      ++wide;
      borrowed += pixel.changed;
    }
  }
  std::printf("blurs under 8 px: %d of %d kept; over 9 px: %d of %d borrowed\n", kept, narrow,
              borrowed, wide);
  EXPECT_GT(narrow, 100);
  EXPECT_EQ(kept, narrow);
  EXPECT_GT(wide, 100);
  EXPECT_GT(borrowed, wide / 2);
}

// Inside a wide near blur, a young pixel whose few rays passed the near surface has the
// background's small CoC of its own; its neighbourhood's rays say how far the near blur reaches
// it, and it gathers over that (it stood out as a single pixel of the background's colour).
TEST(HybridSpatial, AYoungPixelWhoseRaysPassedANearBlurGathersAsItsNeighbours) {
  SpatialFrame frame;
  int passed = 0, borrowed = 0;
  for (const SpatialFrame::Pixel& pixel : frame.traced) {
    if (pixel.ownBlur >= 7.5f || pixel.blur <= 9.0f) continue;
    ++passed;
    borrowed += pixel.changed;
  }
  std::printf("pixels whose rays passed a near blur over 9 px: %d of %d borrowed\n", borrowed,
              passed);
  EXPECT_GT(passed, 20);
  EXPECT_GT(borrowed, passed / 2);
}

TEST(HybridMode, RendersThroughTheFramePipeline) {
  RenderSpec spec;
  spec.width = 192;
  spec.height = 108;
  spec.lens.fNumber = 1.4f;
  ImageRgba8 postProcess = renderImage(spec, RenderMode::PostProcess);
  ImageRgba8 hybrid = renderImage(spec, RenderMode::Hybrid, 2, 3);
  double psnr = compareImages(hybrid, postProcess).psnrDb;
  EXPECT_GT(psnr, 20.0) << "the hybrid starts from the post-process";
  EXPECT_LT(psnr, 60.0) << "and traces rays where the mask asks";

  SceneOnGpu& scene = testScene("builtin:dof");
  FramePipeline pipeline(testContext(), scene.scene, *scene.gpu, spec.width, spec.height);
  FrameRequest request;
  request.mode = RenderMode::Hybrid;
  request.camera = Camera::fromScene(scene.scene.cameras.front());
  request.lens = onSceneCameraSensor(Lens{50.0f, 1.4f, *scene.scene.cameras.front().focusDistance},
                                     scene.scene.cameras.front(), spec.width, spec.height);
  request.settings = {spec.width, spec.height, 0, 2};
  FrameStats stats = pipeline.render(request);
  EXPECT_GT(stats.maskCoverage, 0.01);
  EXPECT_LT(stats.maskCoverage, 0.8);
  EXPECT_GT(stats.passMsOf("hybrid_trace"), 0.0);
}

// The ray mask's edges and their spread depend on the raster's depth and normals and on the lens
// alone, and a still view's further samples add colour only: made from the second frame of a still
// view (the first of those samples), they stand over its later frames, and once its raster has all
// its samples, until the lens changes (in whichever mode) or the raster starts over.
TEST(HybridMode, AStillViewKeepsItsMaskEdgesUntilTheLensOrTheRasterChanges) {
  SceneOnGpu& scene = testScene("builtin:dof");
  constexpr uint32_t kW = 192, kH = 108;
  FramePipeline pipeline(testContext(), scene.scene, *scene.gpu, kW, kH);
  FrameRequest request;
  request.mode = RenderMode::Hybrid;
  request.camera = Camera::fromScene(scene.scene.cameras.front());
  float focus = *scene.scene.cameras.front().focusDistance;
  request.lens = onSceneCameraSensor(Lens{50.0f, 1.4f, focus}, scene.scene.cameras.front(), kW, kH);
  request.settings = {kW, kH, 0, 2};
  auto edges = [&](RenderMode mode = RenderMode::Hybrid) {
    request.mode = mode;
    FrameStats stats = pipeline.render(request);
    if (mode == RenderMode::Hybrid) {
      EXPECT_GT(stats.passMsOf("hybrid_trace"), 0.0);
    }
    return std::any_of(stats.passMs.begin(), stats.passMs.end(),
                       [](const auto& pass) { return pass.first == "ray_mask_edges"; });
  };
  EXPECT_TRUE(edges()) << "a cut: the first sample sets depth and normals";
  EXPECT_TRUE(edges()) << "the first of the still view's further samples";
  EXPECT_FALSE(edges()) << "a further sample: depth and normals as they were";
  request.lens.focusDistance = focus * 0.9f;
  EXPECT_TRUE(edges()) << "the focus changed while the raster takes samples";
  EXPECT_TRUE(edges()) << "the lens rests again: the resting view's edges join the mask";
  for (uint32_t i = 5; i < gpu::kStillRasterFrames; ++i)
    EXPECT_FALSE(edges()) << "frame " << i << " adds a sample";
  request.lens.focusDistance = focus;
  EXPECT_TRUE(edges()) << "the focus changed";
  EXPECT_TRUE(edges()) << "the lens rests again";
  EXPECT_FALSE(edges()) << "a settled raster and the same lens";
  request.lens.focusDistance = focus * 1.2f;
  EXPECT_TRUE(edges()) << "the focus changed";
  EXPECT_TRUE(edges()) << "the lens rests again";
  EXPECT_FALSE(edges());
  request.lens.fNumber = 2.8f;
  EXPECT_FALSE(edges(RenderMode::PostProcess));
  EXPECT_TRUE(edges()) << "the aperture changed while the post-process alone ran";
  EXPECT_FALSE(edges(RenderMode::PostProcess));
  EXPECT_FALSE(edges()) << "the post-process left the mask as it was";
  request.camera.position += request.camera.up * 0.01f;
  EXPECT_TRUE(edges()) << "the camera moved";
}

// The built-in scene wide open, and its reference (rendered once for the tests below).
RenderSpec wideOpen() {
  RenderSpec spec;
  spec.width = 256;
  spec.height = 144;
  spec.lens.fNumber = 1.4f;
  return spec;
}

// A frame pipeline of wideOpen() in hybrid mode at 4 rays per pixel.
struct WideOpenHybrid {
  FrameStats render(uint32_t frameIndex) {
    request.settings.frameIndex = frameIndex;
    return pipeline.render(request);
  }
  RenderSpec spec = [] {
    RenderSpec spec = wideOpen();
    spec.mode = RenderMode::Hybrid;
    spec.raysPerPixel = 4;
    return spec;
  }();
  SceneOnGpu& scene = testScene(spec.scene);
  FramePipeline pipeline{testContext(), scene.scene, *scene.gpu, spec.width, spec.height};
  FrameRequest request = requestFor(spec, scene.scene);
};

// The last frame of a truck of `frames` frames (renderTruckOnto) ending at the spec's view.
ImageRgba8 truckImage(const RenderSpec& spec, RenderMode mode, uint32_t rays, int frames,
                      float step) {
  SceneOnGpu& scene = testScene(spec.scene);
  FramePipeline pipeline(testContext(), scene.scene, *scene.gpu, spec.width, spec.height);
  FrameRequest request = requestFor(spec, scene.scene);
  request.mode = mode;
  request.settings.samplesPerPixel = rays;
  renderTruckOnto(pipeline, request, frames, step);
  return pipeline.image();
}

const ImageRgba8& wideOpenReference() {
  static const ImageRgba8 reference = renderImage(wideOpen(), RenderMode::Reference, 256);
  return reference;
}

// PSNR against the reference over the whole image and over the region (255 inside).
std::pair<double, double> psnrOf(const ImageRgba8& image, const ImageRgba8& reference,
                                 const ImageRgba8& region) {
  return {compareImages(image, reference).psnrDb, compareImages(image, reference, &region).psnrDb};
}

TEST(HybridMode, BeatsThePostProcessWhereItMustInventTheBackground) {
  RenderSpec spec = wideOpen();
  ImageRgba8 region = maskImage(occlusionRegion(spec), spec.width, spec.height);
  const ImageRgba8& reference = wideOpenReference();
  double postProcess =
      compareImages(renderImage(spec, RenderMode::PostProcess), reference, &region).psnrDb;
  double hybrid =
      compareImages(renderImage(spec, RenderMode::Hybrid, 4, 16), reference, &region).psnrDb;
  std::printf("occlusion region: postprocess %.2f dB, hybrid %.2f dB\n", postProcess, hybrid);
  EXPECT_GT(hybrid, postProcess + 3.0);
}

// The first frame of a view, before any history: where the hybrid's few rays are noisier than
// the post-process is wrong, the post-process shares the pixel, so the hybrid is never worse.
TEST(HybridMode, FirstFrameIsAtLeastAsGoodAsThePostProcess) {
  RenderSpec spec = wideOpen();
  ImageRgba8 region = maskImage(occlusionRegion(spec), spec.width, spec.height);
  const ImageRgba8& reference = wideOpenReference();
  ImageRgba8 postProcess = renderImage(spec, RenderMode::PostProcess);
  ImageRgba8 hybrid = renderImage(spec, RenderMode::Hybrid, 4);
  auto [ppWhole, ppRegion] = psnrOf(postProcess, reference, region);
  auto [hybridWhole, hybridRegion] = psnrOf(hybrid, reference, region);
  std::printf(
      "first frame: postprocess %.2f dB (occlusion %.2f), hybrid %.2f dB (occlusion %.2f)\n",
      ppWhole, ppRegion, hybridWhole, hybridRegion);
  EXPECT_GE(hybridWhole, ppWhole - 0.1);
  EXPECT_GE(hybridRegion, ppRegion - 0.1);
}

// In motion the traced history is resampled where the surfaces were (Catmull-Rom between the
// texels): read from the nearest texel, it moved by up to half a pixel at every frame, and the
// traced colour, misplaced at edges, was worth less than its rays. After a truck of 13 frames at
// 16 rays per pixel a frame, the hybrid is as good as the post-process over the whole image and
// better where the post-process cannot see behind the near blur (read from the nearest texel,
// with the composite's trust of a still view: 0.29 dB below it over the whole image and 2.3 dB
// above it there; now 0.04 and 4.3 dB above).
TEST(HybridMode, InMotionItsRaysBeatThePostProcessWhereItMustInventTheBackground) {
  RenderSpec spec = wideOpen();
  ImageRgba8 region = maskImage(occlusionRegion(spec), spec.width, spec.height);
  const ImageRgba8& reference = wideOpenReference();
  auto moving = [&](RenderMode mode) {
    return psnrOf(truckImage(spec, mode, 16, 13, 0.004f), reference, region);
  };
  auto [ppWhole, ppRegion] = moving(RenderMode::PostProcess);
  auto [hybridWhole, hybridRegion] = moving(RenderMode::Hybrid);
  std::printf("in motion: postprocess %.2f dB (occlusion %.2f), hybrid %.2f dB (occlusion %.2f)\n",
              ppWhole, ppRegion, hybridWhole, hybridRegion);
  EXPECT_GT(hybridWhole, ppWhole - 0.15);
  EXPECT_GT(hybridRegion, ppRegion + 3.0);
}

// In motion too, a far blur that the post-process renders well (window bars against the sky,
// behind a mantelpiece in focus) keeps most of its colour: the history's window is a few frames,
// the traced colour's noise unmeasured, and shown inside the traced region with a moving pixel's
// full trust it stippled the bars' blurred edges. After a truck of 13 frames at 4 rays a frame:
// the hybrid 39.14 dB against the post-process's 39.46 so, 39.44 at half the weight.
TEST(HybridMode, InMotionAFarBlurThePostProcessRendersWellIsNotStippled) {
  RenderSpec spec;
  spec.scene = kLivingRoom;
  spec.camera = "overview";
  spec.eye = glm::vec3(3.4f, 1.15f, -0.9f);
  spec.target = glm::vec3(1.5f, 1.0f, 0.4f);
  spec.width = 640;
  spec.height = 360;
  spec.lens = Lens{32.0f, 2.0f, 1.2f};
  const ImageRgba8 reference = renderImage(spec, RenderMode::Reference, 256);
  auto moving = [&](RenderMode mode) {
    return compareImages(truckImage(spec, mode, 4, 13, 0.012f), reference).psnrDb;
  };
  double postProcess = moving(RenderMode::PostProcess);
  double hybrid = moving(RenderMode::Hybrid);
  std::printf("in motion: postprocess %.2f dB, hybrid %.2f dB\n", postProcess, hybrid);
  EXPECT_GT(hybrid, postProcess - 0.15);
}

// A resting view only gets better: each frame's rays are worth more than the post-process they
// replace (no dip while the composite hands pixels with few rays over to their traced colour).
TEST(HybridMode, AStillViewKeepsImproving) {
  // Wider open than wideOpen(): blurs wide enough on both sides of their edges that the mask
  // gives them fewer rays.
  RenderSpec spec = wideOpen();
  spec.lens.fNumber = 0.7f;
  const ImageRgba8 reference = renderImage(spec, RenderMode::Reference, 256);
  double previous = 0.0;
  for (uint32_t frames : {8u, 16u, 20u, 24u, 32u}) {
    double psnr = compareImages(renderImage(spec, RenderMode::Hybrid, 4, frames), reference).psnrDb;
    std::printf("hybrid, %u frames: %.2f dB\n", frames, psnr);
    EXPECT_GE(psnr, previous - 0.05) << frames << " frames";
    previous = psnr;
  }
}

// A far-field blur that the post-process renders well (the edges of a picture frame, a sofa and a
// wall behind a table in focus): the traced colour is shown where it differs from the post-process
// by more than its noise, so the hybrid does not fall while its rays are still noisier than the
// post-process. Handed over by their count alone, it read 42.27 dB at 8 frames, 41.62 at 12 and
// 42.10 at 16, under the post-process's 42.61 (smaller images do not show it: at 480x270 the
// post-process's error is larger).
TEST(HybridMode, AFarBlurThePostProcessRendersWellKeepsItsColourWhileTheRaysAreNoisier) {
  RenderSpec spec;
  spec.scene = kLivingRoom;
  spec.camera = "overview";
  spec.eye = glm::vec3(2.6f, 0.9f, -0.6f);
  spec.target = glm::vec3(2.0f, 0.8f, -4.0f);
  spec.width = 640;
  spec.height = 360;
  spec.lens = Lens{32.0f, 2.0f, 1.15f};
  const ImageRgba8 reference = renderImage(spec, RenderMode::Reference, 256);
  double postProcess =
      compareImages(renderImage(spec, RenderMode::PostProcess, 1, 16), reference).psnrDb;
  double previous = 0.0;
  for (uint32_t frames : {8u, 12u, 16u}) {
    double hybrid =
        compareImages(renderImage(spec, RenderMode::Hybrid, 4, frames), reference).psnrDb;
    std::printf("postprocess %.2f dB, hybrid %u frames %.2f dB\n", postProcess, frames, hybrid);
    EXPECT_GE(hybrid, previous) << frames << " frames";
    previous = hybrid;
  }
  EXPECT_GE(previous, postProcess);
}

// Once a view has rested until the raster has all its samples, every pixel gets rays (those the
// mask leaves out one a frame): the hybrid goes on converging to the ray-traced image rather than
// stopping at the post-process's where the mask saw nothing to do.
TEST(HybridMode, ARestingViewTracesEveryPixel) {
  WideOpenHybrid hybrid;
  const RenderSpec& spec = hybrid.spec;
  for (uint32_t frame = 0; frame <= gpu::kStillRasterFrames; ++frame) {
    FrameStats stats = hybrid.render(frame);
    if (frame < gpu::kStillRasterFrames)
      EXPECT_LT(stats.maskCoverage, 0.8) << "frame " << frame;
    else
      EXPECT_EQ(stats.maskCoverage, 1.0) << "frame " << frame;
  }
  const ImageRgba8& reference = wideOpenReference();
  double at16 = compareImages(renderImage(spec, RenderMode::Hybrid, 4, 16), reference).psnrDb;
  double at48 = compareImages(renderImage(spec, RenderMode::Hybrid, 4, 48), reference).psnrDb;
  double rayTrace = compareImages(renderImage(spec, RenderMode::RayTrace, 4, 48), reference).psnrDb;
  std::printf("hybrid 16 frames %.2f dB, 48 frames %.2f dB; raytrace 48 frames %.2f dB\n", at16,
              at48, rayTrace);
  EXPECT_GT(at48, at16 + 1.6) << "the mask's pixels alone gain 1.1 dB";
}

// A long rest keeps converging: each frame's share of the average is tiny by then, and a history
// that rounded it away drifted (half floats made the image darker frame by frame: 2.1 levels of
// 255 at 256 frames here, 38.2 dB where 64 frames had 39.1).
TEST(HybridMode, ALongRestKeepsConverging) {
  RenderSpec spec = wideOpen();
  const ImageRgba8& reference = wideOpenReference();
  double at64 = compareImages(renderImage(spec, RenderMode::Hybrid, 4, 64), reference).psnrDb;
  ImageRgba8 image = renderImage(spec, RenderMode::Hybrid, 4, 256);
  double at256 = compareImages(image, reference).psnrDb;
  double drift = 0.0;  // mean difference from the reference, in 8-bit levels
  for (size_t i = 0; i < image.pixels.size(); ++i)
    if (i % 4 != 3) drift += double(image.pixels[i]) - double(reference.pixels[i]);
  drift /= double(image.pixels.size()) * 0.75;
  std::printf("hybrid 64 frames %.2f dB, 256 frames %.2f dB; mean difference %.3f levels\n", at64,
              at256, drift);
  EXPECT_GE(at256, at64);
  EXPECT_LT(std::abs(drift), 0.5);
}

// Over a long rest, the quiet pixels that the composite shows as traced alone take their rays in
// turns (ray_mask_rays.comp): fewer pixels listed a frame for as many rays, the image as good.
// A frame of a debug view draws over the whole image, so the frame after it lists every pixel
// again, and shows none of the view.
TEST(HybridMode, ALongRestTakesItsTrustedQuietPixelsInTurns) {
  WideOpenHybrid hybrid;
  const RenderSpec& spec = hybrid.spec;
  FramePipeline& pipeline = hybrid.pipeline;
  FrameRequest& request = hybrid.request;
  FrameStats stats;
  for (uint32_t frame = 0; frame < 96; ++frame) stats = hybrid.render(frame);
  const double pixels = double(spec.width) * spec.height;
  std::printf("after 96 frames: %.1f%% of the pixels listed, %.2f rays per pixel\n",
              100.0 * stats.maskCoverage, double(stats.raysShot) / pixels);
  EXPECT_LT(stats.maskCoverage, 0.9);
  EXPECT_GE(double(stats.raysShot), pixels);
  const ImageRgba8 rested = pipeline.image();
  double at64 =
      compareImages(renderImage(spec, RenderMode::Hybrid, 4, 64), wideOpenReference()).psnrDb;
  double at96 = compareImages(rested, wideOpenReference()).psnrDb;
  std::printf("hybrid 64 frames %.2f dB, 96 frames %.2f dB\n", at64, at96);
  EXPECT_GE(at96, at64);

  request.view = DebugView::FocusZone;
  pipeline.render(request);
  request.view = DebugView::Final;
  EXPECT_EQ(pipeline.render(request).maskCoverage, 1.0);
  EXPECT_GT(compareImages(pipeline.image(), rested).psnrDb, 50.0);
  EXPECT_LT(pipeline.render(request).maskCoverage, 0.9);
}

// On a resting view, an in-focus pixel's traced rays and the raster's jittered samples estimate
// the same antialiased pixel, so its rays count for their number from the first frames: after 4
// frames the hybrid is within 2.5 dB of the ray tracer given as many (33.5 against 35.3 dB; 32.3
// while the rays counted only from 32 of them on).
TEST(HybridMode, AStillViewsRaysCountAsSamplesFromItsFirstFrames) {
  auto psnrAfter4Frames = [](RenderMode mode) {
    return compareImages(renderImage(wideOpen(), mode, 4, 4), wideOpenReference()).psnrDb;
  };
  double rayTrace = psnrAfter4Frames(RenderMode::RayTrace);
  double hybrid = psnrAfter4Frames(RenderMode::Hybrid);
  std::printf("4 still frames: raytrace %.2f dB, hybrid %.2f dB\n", rayTrace, hybrid);
  EXPECT_GE(hybrid, rayTrace - 2.5);
}

// A focus pull on a resting view (the raster stands, only the lens moves): the traced layers follow
// the focus as they follow the image in motion, so that no frame of the pull shows the blur of a
// focus the lens has left, and each is better than the post-process's. Its rays go where the
// lens needs them, not to the resting view's edges (in-focus edges that the pull's few rays
// would not hand over; with them, 35.93 dB here instead of 36.22, at 0.47-0.50 of the pixels
// instead of 0.30-0.31 against 0.54 at rest).
TEST(HybridMode, AFocusPullOnAStillViewFollowsTheFocus) {
  RenderSpec spec = wideOpen();
  spec.raysPerPixel = 4;
  const ImageRgba8& reference = wideOpenReference();
  SceneOnGpu& scene = testScene(spec.scene);
  // The focus rests at 0.6 times the camera's until the raster has all its samples, then moves
  // to 1.4 times it over 8 frames: the fourth of them is focused where the reference is.
  double restingCoverage = 0.0;
  auto midPull = [&](RenderMode mode) {
    spec.mode = mode;
    FrameRequest request = requestFor(spec, scene.scene);
    const float focus = request.lens.focusDistance;
    FramePipeline pipeline(testContext(), scene.scene, *scene.gpu, spec.width, spec.height);
    for (uint32_t frame = 0; frame < gpu::kStillRasterFrames + 4; ++frame) {
      uint32_t pulled = frame < gpu::kStillRasterFrames ? 0 : frame + 1 - gpu::kStillRasterFrames;
      request.lens.focusDistance = focus * (0.6f + 0.1f * float(pulled));
      request.settings.frameIndex = frame;
      FrameStats stats = pipeline.render(request);
      if (mode != RenderMode::Hybrid) continue;
      if (pulled == 0) {
        restingCoverage = stats.maskCoverage;
      } else {
        EXPECT_LE(stats.maskCoverage, 0.75 * restingCoverage)
            << "pull frame " << pulled << " traces the resting view's edges";
      }
    }
    return compareImages(pipeline.image(), reference).psnrDb;
  };
  double postProcess = midPull(RenderMode::PostProcess);
  double hybrid = midPull(RenderMode::Hybrid);
  std::printf("in a focus pull: postprocess %.2f dB, hybrid %.2f dB\n", postProcess, hybrid);
  EXPECT_GE(hybrid, postProcess);
}

// In a corner of the living room, focused across it at 4 m (f/1.4, 50 mm): the wall beside the lens
// blurs over more of the image than the post-process renders (kDofMaxCoc), which shows it too
// narrow and too solid; only rays show the room through all of its blur. The mask traces that
// far and the composite shows those rays from the first: after 8 frames the hybrid is far nearer
// the reference than the post-process, on the whole image and the partial-occlusion region.
TEST(HybridMode, ANearBlurWiderThanThePostProcessRendersIsTraced) {
  RenderSpec spec;
  spec.scene = kLivingRoom;
  spec.camera = "closeup";
  spec.eye = glm::vec3(0.0f, 1.25f, 0.0f);
  spec.target = glm::vec3(0.15f, 0.55f, -4.45f);
  spec.width = 192;
  spec.height = 108;
  spec.lens = Lens{50.0f, 1.4f, 4.0f};
  ImageRgba8 region = maskImage(occlusionRegion(spec), spec.width, spec.height);
  const ImageRgba8 reference = renderImage(spec, RenderMode::Reference, 128);
  ImageRgba8 postProcess = renderImage(spec, RenderMode::PostProcess);
  ImageRgba8 hybrid = renderImage(spec, RenderMode::Hybrid, 4, 8);
  auto [ppWhole, ppRegion] = psnrOf(postProcess, reference, region);
  auto [hybridWhole, hybridRegion] = psnrOf(hybrid, reference, region);
  std::printf(
      "a wall blurred past kDofMaxCoc: postprocess %.2f dB (occlusion %.2f), hybrid 8 "
      "frames %.2f dB (occlusion %.2f)\n",
      ppWhole, ppRegion, hybridWhole, hybridRegion);
  EXPECT_GT(hybridWhole, ppWhole + 6.0);
  EXPECT_GT(hybridRegion, ppRegion + 6.0);
}

// Where a near blur wider than the post-process renders reaches (ray_mask_far.comp's tiles), the
// composite shows the traced colour from the first frame. Across the border of the tiles it marks
// the traced colour's share fades over a tile: switched there, the tiles' rectangles stood out of
// the post-process around them. The share of a pixel: how far its colour lies from the
// post-process's towards the traced one.
TEST(HybridComposite,
     TheTracedShareFadesAcrossTheBorderOfTheTilesABlurBeyondThePostProcessReaches) {
  RenderSpec spec;
  spec.scene = kLivingRoom;
  spec.camera = "closeup";
  spec.width = 640;
  spec.height = 360;
  spec.lens = Lens{50.0f, 0.5f, 2.4f};
  spec.mode = RenderMode::Hybrid;
  spec.raysPerPixel = 4;
  std::unique_ptr<FramePipeline> pipeline = renderFirstFrame(spec);
  const FrameImages& images = pipeline->images();
  std::vector<glm::vec4> farTiles = readImage(images.mask.farTiles);
  std::vector<glm::vec4> rays = readImage(images.mask.rays);
  std::vector<glm::vec4> postProcess = readImage(images.dof.output);
  std::vector<glm::vec4> composite = readImage(images.hybrid.output);
  std::vector<glm::vec4> near = readImage(images.hybrid.reconstructedNear);
  std::vector<glm::vec4> far = readImage(images.hybrid.reconstructedFar);
  const int tile = int(gpu::kDofTileSize), tilesX = int(images.mask.farTiles.width());
  auto marked = [&](int x, int y) { return farTiles[size_t(y / tile * tilesX + x / tile)].x > 0; };
  // The traced share, where the traced colour and the post-process's differ enough to tell.
  auto share = [&](int x, int y) -> std::optional<float> {
    size_t i = size_t(y) * spec.width + size_t(x);
    glm::vec3 pp = postProcess[i], traced = glm::vec3(near[i]) + glm::vec3(far[i]);
    glm::vec3 apart = traced - pp;
    if (rays[i].x == 0.0f || glm::dot(apart, apart) < 0.01f) return std::nullopt;
    return glm::dot(glm::vec3(composite[i]) - pp, apart) / glm::dot(apart, apart);
  };
  // Neighbouring pixels with a marked tile on one side only.
  std::vector<float> steps;
  for (int y = 0; y < int(spec.height); ++y) {
    for (int x = 0; x < int(spec.width); ++x) {
      for (glm::ivec2 next : {glm::ivec2(x + 1, y), glm::ivec2(x, y + 1)}) {
        if (next.x >= int(spec.width) || next.y >= int(spec.height)) continue;
        if (marked(x, y) == marked(next.x, next.y)) continue;
        std::optional<float> a = share(x, y), b = share(next.x, next.y);
        if (a && b) steps.push_back(std::abs(*a - *b));
      }
    }
  }
  ASSERT_GT(steps.size(), 10u);
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  float median = steps[steps.size() / 2];
  std::printf("%zu pixel pairs across the marked tiles' border: median step of the share %.3f\n",
              steps.size(), median);
  EXPECT_LT(median, 0.25f);
}

// With every pixel traced, the hybrid is a ray tracer with a different reconstruction: its image
// comes within 1 dB of raytrace's at the same rays against the reference, and close to it.
TEST(HybridMode, WithAFullMaskMatchesRayTrace) {
  RenderSpec spec = wideOpen();
  const ImageRgba8& reference = wideOpenReference();
  ImageRgba8 rayTrace = renderImage(spec, RenderMode::RayTrace, 4, 16);
  spec.traceEverywhere = true;
  ImageRgba8 hybrid = renderImage(spec, RenderMode::Hybrid, 4, 16);
  double rayTraceDb = compareImages(rayTrace, reference).psnrDb;
  double hybridDb = compareImages(hybrid, reference).psnrDb;
  double betweenDb = compareImages(hybrid, rayTrace).psnrDb;
  std::printf(
      "against the reference: raytrace %.2f dB, hybrid with a full mask %.2f dB; "
      "between them %.2f dB\n",
      rayTraceDb, hybridDb, betweenDb);
  EXPECT_GT(hybridDb, rayTraceDb - 1.0);
  EXPECT_GT(betweenDb, 30.0);
  spec.traceEverywhere = false;
  EXPECT_LT(compareImages(renderImage(spec, RenderMode::Hybrid, 4, 16), reference).psnrDb, hybridDb)
      << "the mask leaves pixels to the post-process";
}

}  // namespace
}  // namespace hdof::test
