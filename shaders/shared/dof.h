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
// From this |CoC| on the half-resolution blur alone is shown; between the focus zone and here it
// is blended with the sharp colour. Downsampling and upsampling blur by about as much as a 4 px
// CoC, so below about 6 px the half-resolution result alone is too blurred.
HDOF_CONST float kDofFullBlurCoc = 6.0;
// Gather kernel: up to kDofMaxRings rings of 8k taps (1 + 4 K (K + 1) taps in all), spaced about
// kDofRingSpacing half-resolution pixels apart where the tile's CoC allows.
HDOF_CONST int kDofMaxRings = 4;
HDOF_CONST float kDofRingSpacing = 1.5;

HDOF_NAMESPACE_END

#ifdef __cplusplus
static_assert(hdof::gpu::kDofTileReach * hdof::gpu::kDofTileSize >= hdof::gpu::kDofMaxCoc / 2.0f,
              "the tile dilation must reach as far as the largest CoC radius");
#endif

#endif
