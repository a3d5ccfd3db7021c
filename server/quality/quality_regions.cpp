#include "quality/quality_regions.h"

namespace hdof {

QualityRegions qualityRegions(const GBufferGeometry& geometry, uint32_t width, uint32_t height,
                              const CocParameters& coc) {
  std::vector<uint8_t> occlusion = occlusionMask(geometry.linearDepth, width, height, coc);
  std::vector<uint8_t> edge =
      edgeBand(geometry.linearDepth, geometry.normals, width, height, coc, occlusion);
  return {maskImage(occlusion, width, height), maskImage(edge, width, height), maskCount(occlusion),
          maskCount(edge)};
}

QualityScores scoreImage(const ImageRgba8& image, const ImageRgba8& reference,
                         const QualityRegions& regions) {
  QualityScores scores;
  scores.whole = compareImages(image, reference);
  if (regions.occlusionPixels)
    scores.occlusion = compareImages(image, reference, &regions.occlusion);
  if (regions.edgePixels) scores.edge = compareImages(image, reference, &regions.edge);
  return scores;
}

}  // namespace hdof
