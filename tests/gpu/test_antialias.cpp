// The raster's anti-aliasing: while the view rests, jittered G-buffer samples average into a
// supersampled image, after which the G-buffer is reused (and the post-process output too, until
// the lens changes); a lens change keeps that average (the raster does not depend on the lens); a
// camera move starts over.
#include "render_fixture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <vector>

namespace hdof::test {
namespace {

constexpr uint32_t kWidth = 240, kHeight = 135;

RenderSpec view(RenderMode mode) {
  RenderSpec spec;
  spec.scene = kLivingRoom;
  spec.camera = "closeup";
  spec.width = kWidth;
  spec.height = kHeight;
  spec.mode = mode;
  spec.lens = Lens{50.0f, 1e6f, 2.4f};  // a pinhole: only the raster's sampling differs
  return spec;
}

// The same view as a pipeline's request, for tests that drive a FramePipeline frame by frame.
FrameRequest closeupRequest(const Scene& scene, RenderMode mode) {
  const SceneCamera& closeup = *scene.findCamera("closeup");
  FrameRequest request;
  request.mode = mode;
  request.camera = Camera::fromScene(closeup);
  request.lens = onSceneCameraSensor(Lens{50.0f, 1e6f, 2.4f}, closeup, kWidth, kHeight);
  request.settings.width = kWidth;
  request.settings.height = kHeight;
  return request;
}

// The pinhole image supersampled: 64 jittered rays per pixel.
const ImageRgba8& supersampled() {
  static const ImageRgba8 image = [] {
    RenderSpec spec = view(RenderMode::Reference);
    spec.raysPerPixel = 64;
    return renderImage(spec);
  }();
  return image;
}

// The first frames after the first raster four samples per pixel where the pixel holds an edge:
// two frames already come near the supersampled image (one more sample per pixel gave about the
// first frame's figure).
TEST(AntiAliasing, AStillViewConvergesToTheSupersampledImage) {
  RenderSpec spec = view(RenderMode::Pinhole);
  double first = compareImages(renderImage(spec), supersampled()).psnrDb;
  spec.frames = 2;
  double two = compareImages(renderImage(spec), supersampled()).psnrDb;
  spec.frames = 16;
  double sixteen = compareImages(renderImage(spec), supersampled()).psnrDb;
  std::printf("pinhole against its supersampled image: 1 frame %.2f dB, 2 frames %.2f dB, 16 "
              "frames %.2f dB\n",
              first, two, sixteen);
  EXPECT_GT(two, first + 3.0);
  EXPECT_GT(sixteen, two + 3.0);
  EXPECT_GT(sixteen, 29.0);
}

// The average of a still view's frames is as bright as the supersampled image: stored at 16-bit
// precision every frame, a running average that the device rounds towards zero loses a fraction
// of a step each time, and the frames after keep it (lib/frame.glsl: nearestHalf). On lavapipe,
// 0.17 of an 8-bit level darker after 16 frames without the rounding, 0.03 with it.
TEST(AntiAliasing, AStillViewsAverageKeepsItsBrightness) {
  auto meanLevel = [](const ImageRgba8& image) {
    double sum = 0.0;
    for (size_t i = 0; i < image.pixels.size(); ++i)
      if (i % 4 != 3) sum += image.pixels[i];
    return sum / (3.0 * image.width * image.height);
  };
  RenderSpec spec = view(RenderMode::Pinhole);
  spec.frames = 16;
  double reference = meanLevel(supersampled()), sixteen = meanLevel(renderImage(spec));
  std::printf("mean 8-bit level: supersampled %.3f, 16 frames %.3f\n", reference, sixteen);
  EXPECT_NEAR(sixteen, reference, 0.06);
}

// The first frame after a cut has one sample per pixel: its edges are smoothed from their
// neighbourhoods, nearer the supersampled image than the samples at the pixel centres.
TEST(AntiAliasing, TheFirstFrameAfterACutSmoothsItsEdges) {
  RenderSpec spec = view(RenderMode::Pinhole);
  spec.pixelJitter = false;
  double centres = compareImages(renderImage(spec), supersampled()).psnrDb;
  spec.pixelJitter = true;
  double smoothed = compareImages(renderImage(spec), supersampled()).psnrDb;
  std::printf("pinhole's first frame against its supersampled image: %.2f dB, the centres %.2f\n",
              smoothed, centres);
  EXPECT_GT(smoothed, centres + 3.0);  // measured 4.8 dB
}

// In motion each frame samples another sub-pixel position and the reprojected history gathers
// them: after a slow truck that ends on the view, its edges are smoother than one sample's.
TEST(AntiAliasing, FramesInMotionGatherJitteredSamples) {
  SceneOnGpu& scene = testScene(kLivingRoom);
  FramePipeline pipeline(testContext(), scene.scene, *scene.gpu, kWidth, kHeight);
  FrameRequest request = closeupRequest(scene.scene, RenderMode::Pinhole);
  request.settings.pixelJitter = false;  // the sample at each pixel centre, as it is
  pipeline.render(request);
  double oneSample = compareImages(pipeline.image(), supersampled()).psnrDb;
  request.settings.pixelJitter = true;
  pipeline.cut();
  renderTruckOnto(pipeline, request, 9, 0.002f);
  double moving = compareImages(pipeline.image(), supersampled()).psnrDb;
  std::printf("pinhole against its supersampled image: one sample %.2f dB, after a truck %.2f dB\n",
              oneSample, moving);
  EXPECT_GT(moving, oneSample + 4.0);  // without jitter in motion: about 2.3 dB
}

// ... and a silhouette leaves no trail: a pixel beside a nearer surface follows that surface's
// motion, so that the edge it shares with it moves with it. With its own motion, the background
// beside the closeup's bottle and table trailed their colour by part of a pixel, which its
// neighbourhood (the silhouette's own pixels) could not clamp.
TEST(AntiAliasing, ASilhouetteInMotionLeavesNoTrail) {
  SceneOnGpu& scene = testScene(kLivingRoom);
  // Pixels within 2 px of a depth step of more than 10%.
  std::vector<float> depth = renderDepth(view(RenderMode::Pinhole));
  ImageRgba8 edges{kWidth, kHeight, std::vector<uint8_t>(size_t(kWidth) * kHeight * 4, 0)};
  uint32_t edgePixels = 0;
  for (int y = 0; y < int(kHeight); ++y)
    for (int x = 0; x < int(kWidth); ++x) {
      float own = depth[size_t(y) * kWidth + x];
      bool near = false;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          int qx = std::clamp(x + dx, 0, int(kWidth) - 1),
              qy = std::clamp(y + dy, 0, int(kHeight) - 1);
          float other = depth[size_t(qy) * kWidth + qx];
          near = near || std::abs(other - own) > 0.1f * std::min(other, own);
        }
      if (!near) continue;
      edges.pixels[(size_t(y) * kWidth + x) * 4] = 255;
      ++edgePixels;
    }
  ASSERT_GT(edgePixels, 1000u);
  FramePipeline pipeline(testContext(), scene.scene, *scene.gpu, kWidth, kHeight);
  FrameRequest request = closeupRequest(scene.scene, RenderMode::Pinhole);
  renderTruckOnto(pipeline, request, 13, 0.004f);
  double psnr = compareImages(pipeline.image(), supersampled(), &edges).psnrDb;
  std::printf("pinhole after a truck, within 2 px of depth steps: %.2f dB\n", psnr);
  EXPECT_GT(psnr, 23.5);  // 21.5 dB with each pixel's own motion, 25.1 with the nearer surface's
}

// Pixels where any channel differs by more than `tolerance`.
uint64_t pixelsOff(const ImageRgba8& a, const ImageRgba8& b, int tolerance) {
  uint64_t count = 0;
  for (size_t i = 0; i < a.pixels.size(); i += 4)
    for (size_t c = 0; c < 3; ++c)
      if (std::abs(int(a.pixels[i + c]) - int(b.pixels[i + c])) > tolerance) {
        ++count;
        break;
      }
  return count;
}

// Each jittered sample is shaded where the raster found its triangle: on builtin:dof (spheres of
// thin triangles, textures at grazing angles) the converged raster and the supersampled rays
// differ only in a few edge pixels, with no specks of a neighbour's extrapolated normals.
TEST(AntiAliasing, EverySampleIsShadedWhereTheRasterFoundIt) {
  RenderSpec spec;
  spec.width = 320;
  spec.height = 180;
  spec.lens = Lens{50.0f, 1e6f, 3.0f};
  spec.mode = RenderMode::Reference;
  spec.raysPerPixel = 64;
  ImageRgba8 reference = renderImage(spec);
  spec.mode = RenderMode::Pinhole;
  spec.frames = 16;
  ImageRgba8 raster = renderImage(spec);
  uint64_t off = pixelsOff(raster, reference, 32);
  double psnr = compareImages(raster, reference).psnrDb;
  std::printf("builtin:dof raster after 16 frames: %.2f dB, %llu pixels off by more than 32\n",
              psnr, (unsigned long long)off);
  EXPECT_LT(off, uint64_t(spec.width) * spec.height / 500);
  EXPECT_GT(psnr, 37.0);
}

TEST(AntiAliasing, ALensChangeKeepsTheAverageAndACameraMoveStartsOver) {
  SceneOnGpu& scene = testScene(kLivingRoom);
  FramePipeline pipeline(testContext(), scene.scene, *scene.gpu, kWidth, kHeight);
  FrameRequest request = closeupRequest(scene.scene, RenderMode::PostProcess);
  auto rasterised = [](const FrameStats& stats) {
    return std::any_of(stats.passMs.begin(), stats.passMs.end(), [](const auto& pass) {
      return pass.first == "visibility" || pass.first == "gbuffer" || pass.first == "antialias";
    });
  };
  auto blurred = [](const FrameStats& stats) {
    return std::any_of(stats.passMs.begin(), stats.passMs.end(),
                       [](const auto& pass) { return pass.first.rfind("dof_", 0) == 0; });
  };
  // The tiles and their lists follow the CoC alone: those of the first further sample (frame 1)
  // stand over the later ones, whose new colour the DoF steps blur.
  auto ran = [](const FrameStats& stats, const std::string& step) {
    return std::any_of(stats.passMs.begin(), stats.passMs.end(),
                       [&](const auto& pass) { return pass.first == step; });
  };
  for (uint32_t i = 0; i < gpu::kStillRasterFrames; ++i) {
    FrameStats stats = pipeline.render(request);
    EXPECT_TRUE(rasterised(stats) && stats.rasterDrawn) << "sample " << i;
    EXPECT_EQ(ran(stats, "dof_tiles") && ran(stats, "dof_tile_lists"), i < 2) << "sample " << i;
    EXPECT_TRUE(ran(stats, "dof_gather")) << "sample " << i;
  }
  double settled = compareImages(pipeline.image(), supersampled()).psnrDb;
  ImageRgba8 before = pipeline.image();
  FrameStats rest = pipeline.render(request);
  EXPECT_FALSE(rasterised(rest) || blurred(rest)) << "nothing changed: the last DoF output stands";
  EXPECT_FALSE(rest.rasterDrawn);
  EXPECT_EQ(pipeline.image().pixels, before.pixels);
  request.lens.focusDistance = 3.0f;  // a focus pull: still a pinhole, same raster
  FrameStats focusPull = pipeline.render(request);
  EXPECT_FALSE(rasterised(focusPull) || focusPull.rasterDrawn)
      << "a settled raster is reused: only the DoF steps run";
  EXPECT_TRUE(blurred(focusPull)) << "the lens changed: the DoF steps run again";
  double afterFocus = compareImages(pipeline.image(), supersampled()).psnrDb;
  EXPECT_GT(afterFocus, settled - 0.5) << "the focus pull kept the raster's samples";

  Camera moved = request.camera;
  moved.position += moved.up * 0.01f;
  request.camera = moved;
  pipeline.render(request);
  request.camera = Camera::fromScene(*scene.scene.findCamera("closeup"));
  pipeline.cut();
  pipeline.render(request);
  double restarted = compareImages(pipeline.image(), supersampled()).psnrDb;
  EXPECT_LT(restarted, settled - 3.0) << "after a cut the view starts from one sample again";
}

// The daemon renders a moving view at a smaller scale and returns to the full size when it rests:
// the frames at the new size start over from their own samples, whatever the raster held at the
// old one (a still view there, or the move's last frame).
TEST(AntiAliasing, ANewViewportStartsOver) {
  SceneOnGpu& scene = testScene(kLivingRoom);
  FramePipeline pipeline(testContext(), scene.scene, *scene.gpu, kWidth, kHeight);
  FrameRequest request = closeupRequest(scene.scene, RenderMode::Pinhole);
  pipeline.render(request);
  ImageRgba8 firstFrame = pipeline.image();
  for (bool stillBefore : {true, false}) {
    SCOPED_TRACE(stillBefore ? "a still view before" : "a move before");
    FrameRequest small = request;
    small.settings.width = kWidth / 2;
    small.settings.height = kHeight / 2;
    if (!stillBefore) small.camera.position += small.camera.up * 0.01f;
    pipeline.resize(small.settings.width, small.settings.height);
    for (int i = 0; i < 3; ++i) pipeline.render(small);
    small.camera = request.camera;  // the move ends where the view rests
    pipeline.render(small);
    pipeline.resize(kWidth, kHeight);
    pipeline.render(request);
    EXPECT_GT(compareImages(pipeline.image(), firstFrame).psnrDb, 35.0);
    for (uint32_t i = 1; i < gpu::kStillRasterFrames; ++i) pipeline.render(request);
    EXPECT_GT(compareImages(pipeline.image(), supersampled()).psnrDb, 35.0);
  }
}

}  // namespace
}  // namespace hdof::test
