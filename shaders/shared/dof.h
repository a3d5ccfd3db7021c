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
// widens a blur by a few pixels and squares its disc, which a bright light's bokeh shows at once
// (even a small share of an HDR light saturates): with this at 5 px, a near light at a CoC of
// -5.5 px showed a rounded square.
HDOF_CONST float kDofSmallBlurCoc = 7.0;
HDOF_CONST float kDofHalfResCoc = 9.0;
// The smallest CoC the composite blurs on a still view (px); below it the sharp colour is within
// 3%.
HDOF_CONST float kDofSubPixelBlurCoc = 0.1;
// Gather kernel: up to kDofMaxRings rings of 8k taps (1 + 4 K (K + 1) taps in all), spaced about
// kDofRingSpacing half-resolution pixels apart where the tile's CoC allows.
HDOF_CONST int kDofMaxRings = 4;
HDOF_CONST float kDofRingSpacing = 1.5;

// The composite's lists of tiles (dof_tile_lists.comp), each an indirect dispatch of one
// workgroup per tile and a pipeline of dof_composite.comp made for what its tiles need (a CPU
// device runs every branch of a shader under a mask, so that code a tile does not need costs
// there as much as code it does): tiles with full-resolution blurs that read only the pixels next
// to each 2x2 quad (every |CoC| under 3 px, no near field); tiles whose blurs read further, with
// no near field in reach; tiles where a small near blur may spread over a pixel too; the last two
// again for blurs that read further still (kDofWideCoc); and the others, which need only the
// sharp colour and the half-resolution layers (dof_composite_layers.comp). List k's entries are
// entries [k * tiles, (k + 1) * tiles) after the header; an entry is a tile's x | y << 16.
HDOF_CONST uint kDofListNarrow = 0;
HDOF_CONST uint kDofListWide = 1;
HDOF_CONST uint kDofListNear = 2;
HDOF_CONST uint kDofListWider = 3;
HDOF_CONST uint kDofListNearWider = 4;
HDOF_CONST uint kDofListLayers = 5;
HDOF_CONST uint kDofListCount = 6;
// A quad's blurs read past the pixels next to it from a |CoC| of 3 px (a radius of 1.5) and, in
// the near field, from a CoC of -1 px: a narrow tile's pixels are inside both.
HDOF_CONST float kDofNarrowCoc = 3.0;
HDOF_CONST float kDofNarrowNearCoc = -1.0;
// The wide and near lists' blurs read 2 px around a pixel, enough for a |CoC| under 5 px (a disc
// of radius 2.5); a tile with a |CoC| from there to kDofHalfResCoc, or a near one as wide within
// reach, goes to the wider or near-wider list, whose blurs read 3 px (up to kDofSmallBlurCoc).
HDOF_CONST float kDofWideCoc = 5.0;

struct DofTileList {
  uint groupsX, groupsY, groupsZ;  // VkDispatchIndirectCommand
  uint reserved;
};

struct DofTileLists {
  DofTileList lists[kDofListCount];
};

HDOF_NAMESPACE_END

#ifdef __cplusplus
#include <cstddef>
static_assert(sizeof(hdof::gpu::DofTileLists) == 16 * hdof::gpu::kDofListCount);
static_assert(hdof::gpu::kDofTileReach * hdof::gpu::kDofTileSize >= hdof::gpu::kDofMaxCoc / 2.0f,
              "the tile dilation must reach as far as the largest CoC radius");
// dof_composite.comp makes the narrow list's pipeline without the half-resolution layers and
// without the sums behind a near pixel.
static_assert(hdof::gpu::kDofNarrowCoc <= hdof::gpu::kDofSmallBlurCoc,
              "a narrow tile's pixels must show no half-resolution layer");
static_assert(hdof::gpu::kDofNarrowNearCoc >= -1.0f,
              "a narrow tile's near pixels must blur over no neighbour (a disc under 0.5 px)");
#endif

#endif
