// Constants of the post-process depth of field (render/postprocess_dof.*, shaders/dof_*.comp),
// shared by C++ and GLSL. CoC values are signed diameters in full-resolution pixels
// (shared/frame.h: signedCocPixels), negative in the near field.
#ifndef HDOF_SHARED_DOF_H
#define HDOF_SHARED_DOF_H
#include "types.h"

HDOF_NAMESPACE_BEGIN

// Full-resolution pixels per side of a CoC tile. A tile is 8x8 half-resolution pixels: one
// workgroup of the gather, so its kernel size is the same for the whole workgroup.
HDOF_CONST uint kDofTileSize = 16;
// The largest |CoC| rendered; larger ones are clamped so that the tile dilation, which looks
// kDofTileReach tiles away, sees every pixel whose blur can reach a tile.
HDOF_CONST float kDofMaxCoc = 64.0;
HDOF_CONST int kDofTileReach = 2;
// |CoC| below the diagonal of a pixel is in focus: the sharp colour is kept exactly.
HDOF_CONST float kDofFocusZone = 1.41421356;
// Up to this |CoC| the composite blurs at full resolution, the near field spreading over what is
// behind it too; from kDofHalfResCoc on the half-resolution layers alone are shown, and between
// the two they are blended. The half-resolution round trip (downsample, gather ramp, upsample)
// widens a blur by a few pixels, which a bright light's bokeh shows at once.
HDOF_CONST float kDofSmallBlurCoc = 5.0;
HDOF_CONST float kDofHalfResCoc = 9.0;
// The smallest CoC the composite blurs on a still view (px); below it the sharp colour is within
// 3%.
HDOF_CONST float kDofSubPixelBlurCoc = 0.1;
// Gather kernel: up to kDofMaxRings rings of 8k taps (1 + 4 K (K + 1) taps in all), spaced about
// kDofRingSpacing half-resolution pixels apart where the tile's CoC allows.
HDOF_CONST int kDofMaxRings = 4;
HDOF_CONST float kDofRingSpacing = 1.5;

// The composite's two lists of tiles (dof_tile_lists.comp), as indirect dispatches of one
// workgroup per tile: the tiles where a pixel's own blur is small enough for the full-resolution
// blurs or a small near blur may spread over a pixel, listed from the front of the entries; the
// others, which need only the sharp colour and the half-resolution layers, from the back. An entry
// is a tile's x | y << 16.
struct DofTileLists {
  uint smallBlurGroupsX, smallBlurGroupsY, smallBlurGroupsZ;  // VkDispatchIndirectCommand
  uint layersGroupsX, layersGroupsY, layersGroupsZ;           // VkDispatchIndirectCommand
  uint reserved0, reserved1;
};

HDOF_NAMESPACE_END

#ifdef __cplusplus
#include <cstddef>
static_assert(sizeof(hdof::gpu::DofTileLists) == 32);
static_assert(offsetof(hdof::gpu::DofTileLists, layersGroupsX) == 12);
static_assert(hdof::gpu::kDofTileReach * hdof::gpu::kDofTileSize >= hdof::gpu::kDofMaxCoc / 2.0f,
              "the tile dilation must reach as far as the largest CoC radius");
#endif

#endif
