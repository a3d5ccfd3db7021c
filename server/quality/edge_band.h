// The in-focus edge band: pixels within a few pixels of a depth or normal edge of the pinhole
// G-buffer whose sharper side is in focus, outside the partial-occlusion region. It is where an
// art director looks for crisp silhouettes and creases (and where a depth of field that bleeds
// blur over sharp edges, or misses antialiasing, shows), as the occlusion region is where the
// background behind a blurred silhouette shows.
#pragma once

#include "quality/occlusion_mask.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace hdof {

struct EdgeBandOptions {
  float radius = 3.0f;  // pixels whose centre is this close (px) to an edge belong to the band
  // An edge is in focus when its sharper side's |CoC| is below this (px): 2 px, a little over the
  // focus zone (shared/dof.h kDofFocusZone, a pixel's diagonal, where the post-process keeps the
  // sharp colour exactly), because a blur under two pixels still reads as a sharp edge and the
  // post-process starts blending its blur in just past the focus zone.
  float inFocusCoc = 2.0f;
  float edgeRatio = 1.1f;        // a neighbour this much deeper (relative) makes a depth edge
  float minDepthStep = 0.02f;    // ... and at least this much deeper, in metres
  float normalAngleDeg = 30.0f;  // neighbours' normals at least this far apart make a normal edge
};

// linearDepth: row-major view depth of a pinhole frame (kBackgroundDepth where nothing is);
// normals: its world normals (zero where nothing is; may be empty: depth edges only); occlusion:
// the partial-occlusion region of the same frame (occlusionMask; may be empty), left out of the
// band. An edge lies between two 4-neighbours; the band is every pixel whose centre is within
// options.radius of the midpoint of such a pair, on both sides. Returns 255 inside, 0 outside.
std::vector<uint8_t> edgeBand(const std::vector<float>& linearDepth,
                              const std::vector<glm::vec3>& normals, uint32_t width,
                              uint32_t height, const CocParameters& coc,
                              const std::vector<uint8_t>& occlusion,
                              const EdgeBandOptions& options = {});

}  // namespace hdof
