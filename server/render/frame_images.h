// Every image and buffer one session's frame pipeline renders into, sized to its viewport, with
// one owner: FrameImages, remade whole for a new viewport. The passes receive the images they read
// and write; none owns any. All colour images stay in VK_IMAGE_LAYOUT_GENERAL (storage and sampled
// use) and start out zero. Half: half the viewport's size, rounded up; tiles: one texel per
// kDofTileSize pixels.
#pragma once

#include "gpu/resources.h"

#include <array>

namespace hdof {

// The G-buffer (gbuffer_pass.h): the raster's visibility and its shaded resolve.
struct GBufferImages {
  GBufferImages(gpu::ImageBatch& batch, const gpu::Context& context, uint32_t w, uint32_t h);
  gpu::Image visibility;    // r32f: the triangle seen at each pixel's sample (-1: none)
  gpu::Image depth;         // d32: the raster's depth buffer
  // The same with kStillRasterSamples samples per pixel: a still view's later frames.
  gpu::Image multisampledVisibility, multisampledDepth;
  // The pixels whose samples see more than one triangle (shared/ray_work.h's list: the header,
  // then an entry per pixel), which the resolve's second step shades.
  gpu::Buffer sharedPixels;
  gpu::Image rasterColor;   // rgba16f: this frame's shaded raster sample (HDR), a: its CoC
  gpu::Image color;         // rgba16f: the sharp colour, anti-aliased over frames (HDR)
  gpu::Image colorHistory;  // rgba16f: the previous frame's `color`
  // rgba16f: the specular part of this frame's sample; a: what the sample counts for in `color`
  gpu::Image specular;
  gpu::Image samplesAveraged;  // r16f: the samples `color` averages
  gpu::Image normalDepth;   // rgba32f: world normal, linear view depth (metres)
  // rg16f: where each pixel's surface was in the previous frame, in pixels from the pixel (for
  // the sky: where its direction was)
  gpu::Image motion;
};

// The post-process depth of field (postprocess_dof.h).
struct DofImages {
  DofImages(gpu::ImageBatch& batch, const gpu::Context& context, uint32_t w, uint32_t h);
  // rgba16f: the sharp colour, alpha the signed CoC in pixels (negative: near field)
  gpu::Image colorCoc;
  // Tiles: largest |CoC|, nearest CoC; tiles (rgba16f) also two flags for the tile lists,
  // dilatedTiles (rg16f) is their dilation.
  gpu::Image tiles, dilatedTiles;
  gpu::Image halfColorCoc, prefiltered;  // rgba16f, half: colour, alpha the CoC
  gpu::Image farLayer, nearLayer;        // rgba16f, half: the gather's (see dof_gather.comp)
  gpu::Image farFiltered, nearFiltered;  // the same after the median
  gpu::Image output;                     // rgba16f: the blurred image, HDR, alpha 1
  gpu::Buffer tileLists;  // the composite's: a DofTileLists header (shared/dof.h), its lists' entries
};

// The adaptive ray mask (ray_mask.h) and the work list it hands to the selective ray trace.
struct RayMaskImages {
  RayMaskImages(gpu::ImageBatch& batch, const gpu::Context& context, uint32_t w, uint32_t h);
  gpu::Image reach;     // r16f: per edge pixel, its disc diameter
  gpu::Image strength;  // rg16f: per edge pixel, its strength and its sharper side's |CoC|
  gpu::Image tiles, dilatedTiles;  // dof_tiles's, on the reach: x the largest
  gpu::Image farRows, farTiles;  // r16f, per tile: ray_mask_far.comp's two passes
  gpu::Image spread;  // rgba16f: the row pass of the disc dilation (half height, strength, |CoC|)
  // rg16f: the column pass (strongest edge or -1, its sharper side's |CoC|); made by FrameImages.
  gpu::Image covered;
  gpu::Image rays;    // r8ui: rays per pixel, 0 where the post-process is enough
  gpu::Buffer workList;    // shared/ray_work.h: header (dispatch arguments), entries
  gpu::Buffer workHeader;  // the list's header, read back for the frame's stats
};

// The hybrid's ray-traced layers (hybrid_dof.h): what the trace writes for the listed pixels,
// the temporal history, and the spatial reconstruction.
struct HybridImages {
  HybridImages(gpu::ImageBatch& batch, uint32_t w, uint32_t h);
  // The trace's, this frame.
  gpu::Image nearLayer;    // rgba16f: average near-layer colour, alpha the hit ratio
  gpu::Image farLayer;     // rgba16f: average far-layer colour, alpha 1 - hit ratio
  gpu::Image farPosition;  // rgba32f: average world position of far hits, w their weight
  gpu::Image layerCoc;     // rg16f: average near |CoC| and far CoC, pixels
  // r32ui, kept from frame to frame: how many rays each pixel has traced so far, so that its
  // next rays continue its sample sequence whatever the mask gave it in earlier frames.
  gpu::Image samplesTraced;
  // The temporal accumulation's, two sets that swap roles each frame. Colours premultiplied by
  // their layer's share of the rays. Single floats: a frame's share of a long average is smaller
  // than half a float's rounding step, which lost it (on a GPU, rounding towards zero, darkened
  // a resting view frame by frame).
  struct History {
    gpu::Image nearLayer;  // rgba32f: near colour x hit ratio, accumulated hit ratio
    gpu::Image farLayer;   // rgba32f: far colour x (1 - ratio), rays accumulated
    gpu::Image moments;    // rgba32f: luminance mean, mean square, rays accumulated, depth
  };
  std::array<History, 2> history;
  // rg16f: luminance variance of one ray and the rays accumulated (0 where the mask did not
  // trace), for the next mask.
  gpu::Image variance;
  // The spatial reconstruction's, as History's near and far layers.
  gpu::Image reconstructedNear, reconstructedFar;
  // rg16f: their difference from the post-process and their noise (hybrid_spatial.comp)
  gpu::Image difference;
  gpu::Image output;  // rgba16f: the composite (or a debug view), HDR
};

// Owned by the frame pipeline, which remakes it for a new viewport once the GPU is done with it.
struct FrameImages {
  FrameImages(const gpu::Context& context, uint32_t width, uint32_t height);
  FrameImages(const FrameImages&) = delete;
  FrameImages& operator=(const FrameImages&) = delete;

  uint32_t width, height;
  gpu::ImageBatch batch;  // before the images: they are made through it
  GBufferImages gbuffer;
  DofImages dof;
  RayMaskImages mask;
  HybridImages hybrid;
  gpu::Image accumulation;  // rgba32f: raytrace and reference's progressive sum, alpha rays
  gpu::Image display;       // rgba8: tonemapped sRGB output
  gpu::Buffer readback;     // display's pixels for the CPU
};

}  // namespace hdof
