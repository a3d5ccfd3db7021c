#include "quality/edge_band.h"

#include <shared/frame.h>
#include <shared/math.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace hdof {

std::vector<uint8_t> edgeBand(const std::vector<float>& depth,
                              const std::vector<glm::vec3>& normals, uint32_t width,
                              uint32_t height, const CocParameters& coc,
                              const std::vector<uint8_t>& occlusion,
                              const EdgeBandOptions& options) {
  std::vector<uint8_t> band(size_t(width) * height, 0);
  const bool hasNormals = !normals.empty();
  const float minCos = std::cos(options.normalAngleDeg * gpu::kPi / 180.0f);
  auto index = [&](int x, int y) { return size_t(y) * width + x; };
  auto absCoc = [&](float z) {
    return std::abs(
        gpu::signedCocPixels(z, coc.apertureDiameter, coc.focusDistance, coc.focalLengthPixels));
  };
  auto isEdge = [&](size_t a, size_t b) {
    float za = depth[a], zb = depth[b];
    float nearZ = std::min(za, zb), farZ = std::max(za, zb);
    if (farZ > nearZ * options.edgeRatio && farZ - nearZ > options.minDepthStep) return true;
    if (!hasNormals) return false;
    const glm::vec3 &na = normals[a], &nb = normals[b];
    // Zero normals (nothing there) make no normal edge; the depth test sees those.
    if (glm::dot(na, na) < 0.25f || glm::dot(nb, nb) < 0.25f) return false;
    return glm::dot(glm::normalize(na), glm::normalize(nb)) < minCos;
  };
  // Marks every pixel whose centre is within the radius of the point halfway between pixel
  // (x, y) and its neighbour (x + ox, y + oy); in doubled coordinates to stay on integers.
  const float r2 = 2.0f * options.radius;
  auto markAround = [&](int x, int y, int ox, int oy) {
    int mx = 2 * x + ox, my = 2 * y + oy;
    int x0 = std::max(0, int(std::floor((float(mx) - r2) / 2.0f)));
    int x1 = std::min(int(width) - 1, int(std::ceil((float(mx) + r2) / 2.0f)));
    int y0 = std::max(0, int(std::floor((float(my) - r2) / 2.0f)));
    int y1 = std::min(int(height) - 1, int(std::ceil((float(my) + r2) / 2.0f)));
    for (int py = y0; py <= y1; ++py) {
      for (int px = x0; px <= x1; ++px) {
        float dx = float(2 * px - mx), dy = float(2 * py - my);
        if (dx * dx + dy * dy <= r2 * r2) band[index(px, py)] = 255;
      }
    }
  };
  const int offsets[2][2] = {{1, 0}, {0, 1}};  // each neighbouring pair once
  for (int y = 0; y < int(height); ++y) {
    for (int x = 0; x < int(width); ++x) {
      for (const auto& o : offsets) {
        int nx = x + o[0], ny = y + o[1];
        if (nx >= int(width) || ny >= int(height)) continue;
        size_t a = index(x, y), b = index(nx, ny);
        if (!isEdge(a, b)) continue;
        // The sharper side decides: a crisp silhouette in front of a blurred background is an
        // in-focus edge, as is a sharp background edge behind a blurred foreground (whose
        // neighbourhood the occlusion region then mostly takes).
        if (std::min(absCoc(depth[a]), absCoc(depth[b])) >= options.inFocusCoc) continue;
        markAround(x, y, o[0], o[1]);
      }
    }
  }
  if (!occlusion.empty())
    for (size_t i = 0; i < band.size(); ++i)
      if (occlusion[i]) band[i] = 0;
  return band;
}

}  // namespace hdof
