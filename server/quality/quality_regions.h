// The regions hdof quality measures besides the whole image, from one pinhole frame's G-buffer:
// the partial-occlusion region (occlusion_mask) and the in-focus edge band (edge_band), as mask
// images for compareImages; and an image's scores against a reference over all three.
#pragma once

#include "image/image.h"
#include "quality/edge_band.h"
#include "quality/gbuffer_geometry.h"
#include "quality/occlusion_mask.h"

#include <optional>

namespace hdof {

struct QualityRegions {
  ImageRgba8 occlusion, edge;  // white inside
  uint64_t occlusionPixels = 0, edgePixels = 0;
};

QualityRegions qualityRegions(const GBufferGeometry& geometry, uint32_t width, uint32_t height,
                              const CocParameters& coc);

struct QualityScores {
  ImageComparison whole;
  std::optional<ImageComparison> occlusion, edge;  // none where the region is empty
};

QualityScores scoreImage(const ImageRgba8& image, const ImageRgba8& reference,
                         const QualityRegions& regions);

}  // namespace hdof
