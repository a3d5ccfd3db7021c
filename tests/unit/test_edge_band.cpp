// The in-focus edge band: a band of the given radius on both sides of a sharp depth or normal
// edge, none for a blurred edge or a plane, never inside the partial-occlusion region.
#include "quality/edge_band.h"

#include <gtest/gtest.h>
#include <shared/frame.h>

#include <cmath>

namespace hdof {
namespace {

constexpr uint32_t kW = 64, kH = 32;
const CocParameters kLens{0.05f, 4.0f, 500.0f};  // 5 cm aperture, focus 4 m

float cocAt(float z) {
  return gpu::signedCocPixels(z, kLens.apertureDiameter, kLens.focusDistance,
                              kLens.focalLengthPixels);
}

// Depth `left` on columns [0, kW / 2), `right` on the rest.
std::vector<float> stepDepth(float left, float right) {
  std::vector<float> depth(kW * kH, right);
  for (uint32_t y = 0; y < kH; ++y)
    for (uint32_t x = 0; x < kW / 2; ++x) depth[y * kW + x] = left;
  return depth;
}

// The columns of row `y` inside the band, as a string of '#' and '.'.
std::string row(const std::vector<uint8_t>& band, uint32_t y) {
  std::string text;
  for (uint32_t x = 0; x < kW; ++x) text += band[y * kW + x] ? '#' : '.';
  return text;
}

// What a band of `radius` px around the boundary between columns kW/2 - 1 and kW/2 looks like.
std::string expectedRow(int radius) {
  std::string text(kW, '.');
  for (int x = 0; x < int(kW); ++x)
    if (std::abs(float(x) - (float(kW) / 2.0f - 0.5f)) <= float(radius)) text[x] = '#';
  return text;
}

TEST(EdgeBand, EmptyForAPlaneWithoutEdges) {
  std::vector<float> depth(kW * kH, 4.0f);
  std::vector<glm::vec3> normals(kW * kH, glm::vec3(0, 0, 1));
  EXPECT_EQ(maskCount(edgeBand(depth, normals, kW, kH, kLens, {})), 0u);
}

TEST(EdgeBand, InFocusDepthStepGivesABandOfTheRadiusOnBothSides) {
  // In focus in front, far behind: the sharper side is the near one.
  std::vector<float> depth = stepDepth(4.0f, 40.0f);
  ASSERT_LT(std::abs(cocAt(4.0f)), 2.0f);
  ASSERT_GT(std::abs(cocAt(40.0f)), 5.0f);
  std::vector<uint8_t> band = edgeBand(depth, {}, kW, kH, kLens, {});
  for (uint32_t y : {0u, kH / 2, kH - 1}) EXPECT_EQ(row(band, y), expectedRow(3)) << y;
  EXPECT_EQ(maskCount(band), uint64_t(6 * kH));  // 3 px on each side of the boundary

  EdgeBandOptions wide;
  wide.radius = 5.0f;
  EXPECT_EQ(row(edgeBand(depth, {}, kW, kH, kLens, {}, wide), kH / 2), expectedRow(5));
}

TEST(EdgeBand, InFocusNormalEdgeGivesABandToo) {
  std::vector<float> depth(kW * kH, 4.0f);
  std::vector<glm::vec3> normals(kW * kH, glm::vec3(0, 0, 1));
  for (uint32_t y = 0; y < kH; ++y)
    for (uint32_t x = 0; x < kW / 2; ++x) normals[y * kW + x] = glm::vec3(1, 0, 0);  // a crease
  std::vector<uint8_t> band = edgeBand(depth, normals, kW, kH, kLens, {});
  EXPECT_EQ(row(band, kH / 2), expectedRow(3));
  EXPECT_EQ(maskCount(edgeBand(depth, {}, kW, kH, kLens, {})), 0u);  // without normals: none
  // A gentle bend is no edge.
  for (uint32_t y = 0; y < kH; ++y)
    for (uint32_t x = 0; x < kW / 2; ++x)
      normals[y * kW + x] = glm::normalize(glm::vec3(0.2f, 0.0f, 1.0f));
  EXPECT_EQ(maskCount(edgeBand(depth, normals, kW, kH, kLens, {})), 0u);
}

TEST(EdgeBand, OutOfFocusEdgeGivesNone) {
  // Both sides blurred: far behind the focus, and a near blurred object in front of them.
  ASSERT_GT(std::abs(cocAt(20.0f)), 2.0f);
  EXPECT_EQ(maskCount(edgeBand(stepDepth(20.0f, 60.0f), {}, kW, kH, kLens, {})), 0u);
  ASSERT_GT(std::abs(cocAt(2.0f)), 2.0f);
  EXPECT_EQ(maskCount(edgeBand(stepDepth(2.0f, 20.0f), {}, kW, kH, kLens, {})), 0u);
  // Just past the threshold on the sharper side: none; raising the threshold brings it back.
  float z = 4.0f * 1.5f;  // |CoC| 2.08 px
  ASSERT_GT(std::abs(cocAt(z)), 2.0f);
  ASSERT_LT(std::abs(cocAt(z)), 3.0f);
  EXPECT_EQ(maskCount(edgeBand(stepDepth(z, 60.0f), {}, kW, kH, kLens, {})), 0u);
  EdgeBandOptions lenient;
  lenient.inFocusCoc = 3.0f;
  EXPECT_GT(maskCount(edgeBand(stepDepth(z, 60.0f), {}, kW, kH, kLens, {}, lenient)), 0u);
}

TEST(EdgeBand, LeavesOutTheOcclusionRegion) {
  // A blurred near object on the left in front of an in-focus wall: the wall's side of the edge
  // is sharp, but the near object's blur (3 px) covers the pixels next to it: that is the
  // occlusion region, not the band; the band keeps the rest of its 3 px.
  std::vector<float> depth = stepDepth(2.7f, 4.0f);
  ASSERT_LT(cocAt(2.7f), -2.0f);
  ASSERT_GT(cocAt(2.7f), -4.0f);
  std::vector<uint8_t> occlusion = occlusionMask(depth, kW, kH, kLens);
  ASSERT_GT(maskCount(occlusion), 0u);
  std::vector<uint8_t> all = edgeBand(depth, {}, kW, kH, kLens, {});
  std::vector<uint8_t> band = edgeBand(depth, {}, kW, kH, kLens, occlusion);
  EXPECT_EQ(row(all, kH / 2), expectedRow(3));
  EXPECT_GT(maskCount(band), 0u);
  EXPECT_LT(maskCount(band), maskCount(all));
  for (size_t i = 0; i < band.size(); ++i) {
    uint8_t expected = occlusion[i] ? 0 : all[i];
    EXPECT_EQ(band[i], expected) << i;
  }
  // A made-up region over the whole image leaves nothing.
  std::vector<uint8_t> everywhere(kW * kH, 255);
  EXPECT_EQ(maskCount(edgeBand(stepDepth(4.0f, 40.0f), {}, kW, kH, kLens, everywhere)), 0u);
}

}  // namespace
}  // namespace hdof
