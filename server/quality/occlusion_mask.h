// The partial-occlusion region, where a post-process has to invent the background: pixels within
// the near-field circle of confusion of a depth edge whose near side is out of focus.
#pragma once

#include "image/image.h"
#include "render/camera.h"

#include <cstdint>
#include <vector>

namespace hdof {

struct CocParameters {
  float apertureDiameter;  // metres
  float focusDistance;     // metres
  float focalLengthPixels;
};

// The CoC parameters of a view rendered at width x height.
CocParameters cocParameters(const Lens& lens, uint32_t width, uint32_t height);

struct OcclusionMaskOptions {
  float edgeRatio = 1.1f;      // a neighbour this much deeper (relative) makes a depth edge
  float minDepthStep = 0.02f;  // ... and at least this much deeper, in metres
};

// linearDepth: row-major view depth of a pinhole frame. Returns 255 inside the region, 0 outside.
std::vector<uint8_t> occlusionMask(const std::vector<float>& linearDepth, uint32_t width,
                                   uint32_t height, const CocParameters& coc,
                                   const OcclusionMaskOptions& options = {});

ImageRgba8 maskImage(const std::vector<uint8_t>& mask, uint32_t width, uint32_t height);
uint64_t maskCount(const std::vector<uint8_t>& mask);

}  // namespace hdof
