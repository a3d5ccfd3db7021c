// The raytrace mode converges towards the reference while the camera rests; the reference traces
// at least its minimum of rays; the partial-occlusion region comes from real depth edges.
#include "quality/occlusion_mask.h"
#include "quality/reference_image.h"
#include "render_fixture.h"

#include <gtest/gtest.h>

#include <cmath>

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

// Two counts of the reference's low-discrepancy rays can agree long before either is near the
// limit: the convergence test only stops the doubling from minRays on, or at maxRays if fewer.
TEST(ConvergedReference, TracesAtLeastItsMinimumOfRays) {
  RenderSpec spec;
  spec.width = 32;
  spec.height = 18;
  spec.mode = RenderMode::Reference;
  auto pipeline = renderFirstFrame(spec);
  FrameRequest request = requestFor(spec, testScene(spec.scene).scene);
  ReferenceOptions options;
  options.targetDb = 11.0;  // met by any two counts
  ReferenceImage reference = renderConvergedReference(*pipeline, request, options);
  EXPECT_TRUE(reference.converged);
  EXPECT_EQ(reference.rays, options.minRays);
  EXPECT_EQ(reference.verdict().find("occlusion region"), std::string::npos)
      << "no region was given: " << reference.verdict();
  options.maxRays = 64;
  reference = renderConvergedReference(*pipeline, request, options);
  EXPECT_TRUE(reference.converged);
  EXPECT_EQ(reference.rays, 64u);
}

// A ray that passes a point light on its way to a surface sees that surface with the light
// straight behind the viewer: the shading's half vector is the view direction, and a dot product of
// unit vectors rounded above 1 once made the Fresnel term NaN (a black pixel, which every blur
// spread into a black square). builtin:dof at f/1.05 has such a ray among its first four per
// pixel (pixel 106, 30), past the point light in front of the brick wall.
TEST(RayTrace, RadianceStaysFiniteWithALightStraightBehindTheViewer) {
  RenderSpec spec;
  spec.width = 480;
  spec.height = 270;
  spec.lens = Lens{50.0f, 1.05f, 4.0f};
  spec.mode = RenderMode::Reference;
  spec.raysPerPixel = 4;
  std::vector<glm::vec4> sums = readImage(renderFirstFrame(spec)->images().accumulation);
  size_t notFinite = 0;
  for (const glm::vec4& sum : sums)
    if (!std::isfinite(sum.r) || !std::isfinite(sum.g) || !std::isfinite(sum.b)) ++notFinite;
  EXPECT_EQ(notFinite, 0u);
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
