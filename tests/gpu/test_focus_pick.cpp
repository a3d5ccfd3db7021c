// Focus picking on the CPU agrees with the raster: the depth under a pixel is the G-buffer's
// linear depth there, wherever the pixel is not on a silhouette.
#include "render/focus_pick.h"
#include "render_fixture.h"

#include <gtest/gtest.h>

namespace hdof::test {
namespace {

TEST(FocusPick, DepthUnderPixelMatchesTheGBuffer) {
  RenderSpec spec;
  spec.width = 96;
  spec.height = 64;
  FrameRequest request;
  std::vector<float> depth = renderDepth(spec, &request);
  const Bvh& bvh = testScene(spec.scene).bvh;
  int compared = 0;
  for (uint32_t y = 1; y + 1 < spec.height; y += 3) {
    for (uint32_t x = 1; x + 1 < spec.width; x += 3) {
      float d = depth[y * spec.width + x];
      // Skip silhouettes (a neighbour at another depth) and the background.
      bool flat = d < 100.0f;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          flat = flat && std::abs(depth[(y + dy) * spec.width + x + dx] - d) < 0.02f * d;
      if (!flat) continue;
      std::optional<float> picked =
          depthUnderPixel(bvh, request.camera, request.lens, spec.width, spec.height, float(x), float(y));
      ASSERT_TRUE(picked) << x << "," << y;
      EXPECT_NEAR(*picked, d, 0.01f * d) << x << "," << y;
      ++compared;
    }
  }
  EXPECT_GT(compared, 100);
}

}  // namespace
}  // namespace hdof::test
