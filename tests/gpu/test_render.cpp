// The raster and the ray tracer agree, the reference converges, and a frame's images make no
// driver compile its shaders anew.
#include "render/frame_images.h"
#include "render_fixture.h"

#include <gtest/gtest.h>

#include <shared/dof.h>

#include <bit>
#include <utility>

namespace hdof::test {
namespace {

RenderSpec pinholeOf(const std::string& scene, const std::string& camera, uint32_t w, uint32_t h) {
  RenderSpec spec;
  spec.scene = scene;
  spec.camera = camera;
  spec.width = w;
  spec.height = h;
  return spec;
}

// A reference with a vanishing aperture through pixel centres sees exactly what the raster sees:
// this checks traversal, shading and camera conventions together.
void expectRasterMatchesRayTrace(const std::string& scene, const std::string& camera,
                                 float znear = 0.0f) {
  RenderSpec raster = pinholeOf(scene, camera, 320, 180);
  raster.znear = znear;
  raster.pixelJitter = false;  // no anti-aliasing either
  RenderSpec traced = raster;
  traced.mode = RenderMode::Reference;
  traced.lens.fNumber = 1e6f;
  ImageRgba8 a = renderImage(raster);
  ImageRgba8 b = renderImage(traced);
  ImageComparison c = compareImages(a, b);
  EXPECT_GE(c.psnrDb, 40.0) << scene << " " << camera;
  // And the image is not trivially empty: it has real contrast.
  uint8_t lo = 255, hi = 0;
  for (size_t i = 0; i < a.pixels.size(); i += 4) {
    lo = std::min(lo, a.pixels[i + 1]);
    hi = std::max(hi, a.pixels[i + 1]);
  }
  EXPECT_GT(hi - lo, 100) << "the image is nearly uniform";
}

// A frame's images have no side that is a power of two, whatever the viewport: llvmpipe would
// compile every shader that binds one again (seconds on the render thread). Sides that would be
// are allocated longer; the steps use the frame's size, not the allocation's.
TEST(Render, FrameImagesKeepClearOfPowerOfTwoSides) {
  for (auto [width, height] : {std::pair{1015u, 700u}, {128u, 72u}, {250u, 140u}, {33u, 2u}}) {
    FrameImages images(testContext(), width, height);
    for (const gpu::Image* image :
         {&images.gbuffer.color, &images.gbuffer.multisampledVisibility, &images.dof.halfColorCoc,
          &images.dof.tiles, &images.mask.farTiles, &images.hybrid.variance, &images.display}) {
      EXPECT_FALSE(std::has_single_bit(image->allocated().width)) << width << "x" << height;
      EXPECT_FALSE(std::has_single_bit(image->allocated().height)) << width << "x" << height;
      EXPECT_LE(image->allocated().width, image->width() + 2);
    }
    EXPECT_EQ(images.dof.tiles.width(), (width + gpu::kDofTileSize - 1) / gpu::kDofTileSize);
    EXPECT_EQ(images.display.width(), width) << "what copies and dispatches cover";
  }
}

TEST(Render, RasterMatchesPinholeRayTraceOnBuiltinScene) {
  expectRasterMatchesRayTrace("builtin:dof", "default");
}

TEST(Render, RasterMatchesPinholeRayTraceOnLivingRoom) {
  expectRasterMatchesRayTrace(kLivingRoom, "closeup");
  expectRasterMatchesRayTrace(kLivingRoom, "overview");
}

// A camera against a wall (or inside an object) sees past what lies in front of its near plane,
// in the raster and in the rays alike: here the plane cuts through the nearest objects.
TEST(Render, RaysHitNothingInFrontOfTheNearPlane) {
  expectRasterMatchesRayTrace("builtin:dof", "default", 3.0f);
}

TEST(Render, ReferenceConvergesAsRaysGrow) {
  RenderSpec spec = pinholeOf("builtin:dof", "default", 96, 54);
  spec.mode = RenderMode::Reference;
  spec.lens.fNumber = 1.4f;
  spec.raysPerPixel = 256;
  ImageRgba8 truth = renderImage(spec);
  double previous = 1e30;
  for (uint32_t rays : {1u, 4u, 16u, 64u}) {
    spec.raysPerPixel = rays;
    double error = meanSquaredError(renderImage(spec), truth);
    EXPECT_LT(error, previous) << rays << " rays per pixel";
    previous = error;
  }
  EXPECT_LT(previous, 40.0);  // 64 rays: within 32 dB of the 256-ray image
}

TEST(Render, WideApertureBlursWhatIsOutOfFocus) {
  // The same view at f/1.4 and as a pinhole differ (depth of field happens) but less so on the
  // in-focus wall than over the whole image of the DoF scene.
  RenderSpec spec = pinholeOf("builtin:wall", "default", 192, 108);
  spec.mode = RenderMode::Reference;
  spec.raysPerPixel = 64;
  spec.lens.fNumber = 1e6f;
  ImageRgba8 sharpWall = renderImage(spec);
  spec.lens.fNumber = 1.4f;
  ImageRgba8 apertureWall = renderImage(spec);
  double wallPsnr = compareImages(sharpWall, apertureWall).psnrDb;
  EXPECT_GT(wallPsnr, 30.0) << "wall in focus stays sharp";

  spec.scene = "builtin:dof";
  spec.lens.fNumber = 1e6f;
  ImageRgba8 sharp = renderImage(spec);
  spec.lens.fNumber = 1.4f;
  ImageRgba8 blurred = renderImage(spec);
  EXPECT_LT(compareImages(sharp, blurred).psnrDb, wallPsnr - 5.0) << "near and far objects blur";
}

TEST(Context, UnknownDeviceIsAClearError) {
  gpu::ContextOptions options;
  options.device = "no-such-device-anywhere";
  try {
    gpu::Context context(options);
    FAIL() << "expected NoVulkanError";
  } catch (const NoVulkanError& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-device-anywhere"), std::string::npos);
  }
}

}  // namespace
}  // namespace hdof::test

namespace hdof::test {
namespace {

// The bokeh's outline: the farthest bright pixel from its centre within +-7.5 degrees of each
// direction, averaged over the six directions at `firstAngle` + k 60 degrees.
double outlineRadius(const ImageRgba8& image, double firstAngle) {
  double cx = 0.0, cy = 0.0, total = 0.0;
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x) {
      double v = image.pixels[(size_t(y) * image.width + x) * 4 + 1];
      cx += v * x, cy += v * y, total += v;
    }
  cx /= total, cy /= total;
  double farthest[6] = {};
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x) {
      if (image.pixels[(size_t(y) * image.width + x) * 4 + 1] < 60) continue;
      double dx = x - cx, dy = cy - y;  // y up
      double angle = std::atan2(dy, dx) * 180.0 / M_PI - firstAngle;
      double sector = std::remainder(angle, 60.0);
      if (std::abs(sector) > 7.5) continue;
      int k = int(std::lround((angle - sector) / 60.0)) % 6;
      farthest[(k + 6) % 6] = std::max(farthest[(k + 6) % 6], std::hypot(dx, dy));
    }
  double sum = 0.0;
  for (double r : farthest) sum += r;
  return sum / 6.0;
}

TEST(Render, ApertureBladesShapeTheRayTracedBokeh) {
  RenderSpec spec;
  spec.scene = "builtin:bokeh";
  spec.width = 480;
  spec.height = 270;
  spec.mode = RenderMode::Reference;
  spec.raysPerPixel = 96;
  spec.lens = Lens{200.0f, 0.5f, 0.0f};
  spec.lens.blades = 6;
  ImageRgba8 hexagon = renderImage(spec);
  // Six blades with a vertex to the right: out to the corners at 0, 60, ... degrees, only to
  // the flat edges (cos 30 = 0.87 of that) at 30, 90, ... degrees.
  double corners = outlineRadius(hexagon, 0.0), edges = outlineRadius(hexagon, 30.0);
  std::printf("hexagon: corners %.1f px, edges %.1f px\n", corners, edges);
  EXPECT_NEAR(edges / corners, 0.87, 0.06);
  spec.lens.blades = 0;
  ImageRgba8 circle = renderImage(spec);
  double a = outlineRadius(circle, 0.0), b = outlineRadius(circle, 30.0);
  std::printf("circle: %.1f px, %.1f px\n", a, b);
  EXPECT_NEAR(b / a, 1.0, 0.06);
}

// An untimed frame (most of the daemon's) writes no timestamps and renders the same image.
TEST(Render, AnUntimedFrameHasNoPassTimesAndTheSameImage) {
  RenderSpec spec = pinholeOf("builtin:dof", "default", 96, 54);
  spec.mode = RenderMode::Hybrid;
  spec.raysPerPixel = 2;
  SceneOnGpu& scene = testScene(spec.scene);
  FrameRequest request = requestFor(spec, scene.scene);
  auto render = [&](bool timed, ImageRgba8& image) {
    FramePipeline pipeline(testContext(), scene.scene, *scene.gpu, spec.width, spec.height);
    request.timePasses = timed;
    FrameStats stats = pipeline.render(request);
    image = pipeline.image();
    return stats;
  };
  ImageRgba8 timedImage, untimedImage;
  FrameStats timed = render(true, timedImage);
  FrameStats untimed = render(false, untimedImage);
  EXPECT_GT(timed.passMsOf("hybrid_trace"), 0.0);
  EXPECT_GT(timed.gpuMs, 0.0);
  EXPECT_TRUE(untimed.passMs.empty());
  EXPECT_EQ(untimed.gpuMs, 0.0);
  EXPECT_GT(untimed.wallMs, 0.0);
  EXPECT_EQ(meanSquaredError(untimedImage, timedImage), 0.0);
}

}  // namespace
}  // namespace hdof::test
