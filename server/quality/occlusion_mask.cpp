#include "quality/occlusion_mask.h"

#include <shared/frame.h>

#include <algorithm>
#include <cmath>

namespace hdof {

CocParameters cocParameters(const Lens& lens, uint32_t width, uint32_t height) {
  return {lens.apertureDiameter(), lens.focusDistance, focalLengthPixels(lens, width, height)};
}

std::vector<uint8_t> occlusionMask(const std::vector<float>& depth, uint32_t width, uint32_t height,
                                   const CocParameters& coc, const OcclusionMaskOptions& options) {
  std::vector<uint8_t> mask(size_t(width) * height, 0);
  auto at = [&](int x, int y) { return depth[size_t(y) * width + x]; };
  const int offsets[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (int y = 0; y < int(height); ++y) {
    for (int x = 0; x < int(width); ++x) {
      float z = at(x, y);
      float c =
          gpu::signedCocPixels(z, coc.apertureDiameter, coc.focusDistance, coc.focalLengthPixels);
      if (c > -std::sqrt(2.0f)) continue;  // not a near-field, out-of-focus pixel
      bool edge = false;
      for (const auto& o : offsets) {
        int nx = x + o[0], ny = y + o[1];
        if (nx < 0 || ny < 0 || nx >= int(width) || ny >= int(height)) continue;
        float neighbour = at(nx, ny);
        edge |= neighbour > z * options.edgeRatio && neighbour - z > options.minDepthStep;
      }
      if (!edge) continue;
      // Everything this pixel's blur disc reaches sees it partly, and what lies behind it.
      float radius = -c * 0.5f;
      int r = int(std::ceil(radius));
      for (int dy = -r; dy <= r; ++dy) {
        int py = y + dy;
        if (py < 0 || py >= int(height)) continue;
        for (int dx = -r; dx <= r; ++dx) {
          int px = x + dx;
          if (px < 0 || px >= int(width) || float(dx * dx + dy * dy) > radius * radius) continue;
          mask[size_t(py) * width + px] = 255;
        }
      }
    }
  }
  return mask;
}

ImageRgba8 maskImage(const std::vector<uint8_t>& mask, uint32_t width, uint32_t height) {
  ImageRgba8 image{width, height, std::vector<uint8_t>(mask.size() * 4)};
  for (size_t i = 0; i < mask.size(); ++i) {
    std::fill_n(&image.pixels[i * 4], 3, mask[i]);
    image.pixels[i * 4 + 3] = 255;
  }
  return image;
}

uint64_t maskCount(const std::vector<uint8_t>& mask) {
  return std::count_if(mask.begin(), mask.end(), [](uint8_t v) { return v != 0; });
}

}  // namespace hdof
