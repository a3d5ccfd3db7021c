// The raster and the ray tracer agree, and the reference converges.
#include "render_fixture.h"

#include <gtest/gtest.h>

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
void expectRasterMatchesRayTrace(const std::string& scene, const std::string& camera) {
  RenderSpec raster = pinholeOf(scene, camera, 320, 180);
  RenderSpec traced = raster;
  traced.mode = RenderMode::Reference;
  traced.lens.fNumber = 1e6f;
  traced.pixelJitter = false;
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

TEST(Render, RasterMatchesPinholeRayTraceOnBuiltinScene) {
  expectRasterMatchesRayTrace("builtin:dof", "default");
}

TEST(Render, RasterMatchesPinholeRayTraceOnLivingRoom) {
  expectRasterMatchesRayTrace(kLivingRoom, "closeup");
  expectRasterMatchesRayTrace(kLivingRoom, "overview");
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
