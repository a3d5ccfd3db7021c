// The partial-occlusion region: empty without depth edges, a band around a blurred near edge.
#include "quality/occlusion_mask.h"

#include <gtest/gtest.h>
#include <shared/frame.h>

namespace hdof {
namespace {

constexpr uint32_t kW = 64, kH = 32;
const CocParameters kLens{0.05f, 4.0f, 500.0f};  // 5 cm aperture, focus 4 m

TEST(OcclusionMask, EmptyForAPlaneWithoutEdges) {
  std::vector<float> depth(kW * kH, 1.0f);  // near and out of focus, but no edge
  EXPECT_EQ(maskCount(occlusionMask(depth, kW, kH, kLens)), 0u);
}

TEST(OcclusionMask, EmptyWhenTheNearSideIsInFocus) {
  std::vector<float> depth(kW * kH, 4.0f);
  for (uint32_t y = 0; y < kH; ++y)
    for (uint32_t x = kW / 2; x < kW; ++x) depth[y * kW + x] = 40.0f;  // far behind focus
  EXPECT_EQ(maskCount(occlusionMask(depth, kW, kH, kLens)), 0u);
}

TEST(OcclusionMask, BandAroundABlurredNearEdgeAsWideAsItsCoc) {
  std::vector<float> depth(kW * kH, 10.0f);
  for (uint32_t y = 0; y < kH; ++y)
    for (uint32_t x = 0; x < kW / 2; ++x) depth[y * kW + x] = 2.0f;  // near object on the left
  float coc = gpu::signedCocPixels(2.0f, kLens.apertureDiameter, kLens.focusDistance,
                                   kLens.focalLengthPixels);
  ASSERT_LT(coc, -4.0f);
  std::vector<uint8_t> mask = occlusionMask(depth, kW, kH, kLens);
  float radius = -coc / 2.0f;
  uint32_t row = kH / 2;
  for (uint32_t x = 0; x < kW; ++x) {
    float distance = std::abs(float(x) - float(kW / 2 - 1));
    bool inside = mask[row * kW + x] != 0;
    if (distance <= radius - 1.0f) {
      EXPECT_TRUE(inside) << x;
    } else if (distance > radius + 1.0f) {
      EXPECT_FALSE(inside) << x;
    }
  }
}

}  // namespace
}  // namespace hdof
