// The adaptive ray mask (render/ray_mask.*, shaders/ray_mask_*.comp) and the work list it hands
// to the selective ray tracer, shared by C++ and GLSL.
//
// Work list buffer: a RayWorkHeader, then one uvec2 per pixel that gets rays:
// x = pixel x | pixel y << 16, y = its ray count. The header starts with a
// VkDispatchIndirectCommand, so vkCmdDispatchIndirect(list, 0) runs one thread per entry in
// workgroups of kRayWorkGroupSize.
#ifndef HDOF_SHARED_RAY_WORK_H
#define HDOF_SHARED_RAY_WORK_H
#include "types.h"

HDOF_NAMESPACE_BEGIN

HDOF_CONST uint kRayWorkGroupSize = 64;

struct RayWorkHeader {
  uint groupsX, groupsY, groupsZ;  // VkDispatchIndirectCommand
  uint count;                      // entries listed
  uint rays;                       // their ray counts' sum
  uint reserved0, reserved1, reserved2;
};

HDOF_CONST uint kRayWorkEntrySize = 8;

HDOF_FN uint packRayWorkPixel(uint x, uint y) { return x | (y << 16u); }
HDOF_FN uvec2 unpackRayWorkPixel(uint packed) { return uvec2(packed & 0xffffu, packed >> 16u); }

// Edge detection thresholds (Canny's hysteresis pair, as a ramp from no rays to all rays).
// Depth: the relative jump in inverse depth across an edge, 1 - z_near / z_far.
HDOF_CONST float kRayMaskDepthJumpLow = 0.08;
HDOF_CONST float kRayMaskDepthJumpHigh = 0.3;
// Normals: the Sobel gradient of the filtered unit normal, per pixel.
HDOF_CONST float kRayMaskNormalLow = 0.15;
HDOF_CONST float kRayMaskNormalHigh = 0.5;
// Far-field edges (their near side behind the focus plane) get rays from this CoC diameter
// (pixels) on, and only for depth jumps: below it the post-process's background gather holds up.
HDOF_CONST float kRayMaskFarEdgeCoc = 2.0;
// The hybrid's spatial reconstruction gathers over a disc of this radius over a pixel's CoC
// (hybrid_spatial.comp): an eighth, so a CoC of 8 px is the first whose disc reaches a neighbour.
HDOF_CONST float kHybridSpatialRadiusOfCoc = 0.125;
// Rays by CoC: a pixel whose nearby edges are blurred on both sides by more than this CoC
// diameter (pixels) gets fewer rays, by the ratio of the blur areas (a quarter at twice it): from
// where the spatial reconstruction fills in from the neighbours, below which fewer rays are only
// more noise.
HDOF_CONST float kRayMaskDenseCoc = 1.0 / kHybridSpatialRadiusOfCoc;
// An edge of the resting view's raster crosses a pixel when a neighbour's normal turns from the
// pixel's by more than this cosine, or its depth jumps by kRayMaskDepthJumpLow.
HDOF_CONST float kRayMaskCrossedNormal = 0.9;
// The widest disc (diameter, pixels) that a near-field edge gets rays over. The post-process
// renders blurs up to kDofMaxCoc; a near object closer to the lens blurs wider, and only rays show
// how far (ray_mask_far.comp marks the tiles such discs reach beyond the pixel dilation's).
HDOF_CONST float kRayMaskFarReach = 512.0;
// The widest band (pixels) traced beside an in-focus silhouette over a blurred background.
HDOF_CONST float kRayMaskSilhouetteReach = 8.0;
// Luminance variance of one ray of the ray-traced output (hybrid_temporal.comp) above which a
// pixel gets rays without an edge, and at which it gets the full sample count.
HDOF_CONST float kRayMaskVarianceOn = 0.001;
HDOF_CONST float kRayMaskVarianceFull = 0.005;
// What the variance reports for a pixel with too little history to estimate it (full rays):
// beyond any variance a ray's luminance has (a ray that meets a light of luminance 200 half the
// time has 10^4), so that a pixel beside a bright light counts as settled and noisy; near the
// largest half float.
HDOF_CONST float kRayMaskVarianceNew = 60000.0;
// Rays a pixel has accumulated from which the hybrid composite shows its traced colour alone
// (hybrid_composite.comp); on a resting view, the ray mask gives such pixels the full rays.
HDOF_CONST float kHybridTrustedRays = 48.0;
// ... and while the camera moves, from half as many: the history's window is short then (it
// lags less), and the post-process, whose raster has one sample a frame, is further from the
// lens's image than at rest.
HDOF_CONST float kHybridMovingTrustedRays = 24.0;
// The composite's noise test (hybrid_spatial.comp writes each pixel's terms, hybrid_composite.comp
// sums them): the frames of a pixel's rays from which their variance is measured well enough (from
// 12 on, the gain between the 8th and the 16th frame was half as large; from 4, the 4th frames of
// the closeup lost 0.3 dB); the rare bright hits below which rays' variance says little of their
// mean's error (a near lamp's bokeh rim in builtin:dof kept the post-process's dimmer disc at 32
// frames); and the share of the noise that counts (at 1, builtin:dof at 32 frames lost 0.06 dB; at
// 0.7 seven views were within 0.1 dB of the count alone or better from 1 to 48 frames).
HDOF_CONST float kNoiseTestFrames = 8.0;
HDOF_CONST float kNoiseTestBrightHits = 10.0;
HDOF_CONST float kNoiseTestShare = 0.7;

HDOF_NAMESPACE_END

#ifdef __cplusplus
#include <cstddef>
static_assert(sizeof(hdof::gpu::RayWorkHeader) == 32);
static_assert(offsetof(hdof::gpu::RayWorkHeader, groupsX) == 0);
static_assert(offsetof(hdof::gpu::RayWorkHeader, count) == 12);
static_assert(offsetof(hdof::gpu::RayWorkHeader, rays) == 16);
#else
// Declares the work list as `workList` at set 1, the binding given.
#define HDOF_RAY_WORK_LIST(bindingIndex, access)                              \
  layout(set = 1, binding = bindingIndex, std430) access buffer RayWorkList { \
    RayWorkHeader header;                                                     \
    uvec2 entries[];                                                          \
  }                                                                           \
  workList
#endif

#endif
