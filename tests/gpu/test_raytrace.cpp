// The raytrace mode converges towards the reference while the camera rests; the partial-occlusion
// region comes from real depth edges.
#include "quality/occlusion_mask.h"
#include "render_fixture.h"

#include <gtest/gtest.h>

namespace hdof::test {
namespace {

TEST(RayTrace, ApproachesTheReferenceAsFramesAccumulate) {
  RenderSpec spec;
  spec.width = 128;
  spec.height = 72;
  spec.lens.fNumber = 1.4f;
  spec.mode = RenderMode::Reference;
  spec.raysPerPixel = 256;
  ImageRgba8 reference = renderImage(spec);
  spec.mode = RenderMode::RayTrace;
  spec.raysPerPixel = 1;
  double previous = 0.0;
  for (uint32_t frames : {1u, 4u, 16u}) {
    spec.frames = frames;
    double psnr = compareImages(renderImage(spec), reference).psnrDb;
    EXPECT_GT(psnr, previous + 2.0) << frames << " frames";
    previous = psnr;
  }
  EXPECT_GT(previous, 30.0);
}

uint64_t regionPixels(const std::string& scene) {
  RenderSpec spec;
  spec.scene = scene;
  spec.width = 160;
  spec.height = 90;
  spec.lens.fNumber = 1.4f;
  return maskCount(occlusionRegion(spec));
}

TEST(OcclusionRegion, EmptyForAWallAndPresentInTheDofScene) {
  EXPECT_EQ(regionPixels("builtin:wall"), 0u);
  EXPECT_GT(regionPixels("builtin:dof"), 160u * 90u / 50u);  // more than 2% of the image
}

}  // namespace
}  // namespace hdof::test
