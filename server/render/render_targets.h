// The images one session renders into, sized to its viewport. All stay in
// VK_IMAGE_LAYOUT_GENERAL (storage and sampled use), except the depth buffer.
#pragma once

#include "gpu/resources.h"

namespace hdof {

struct RenderTargets {
  RenderTargets(const gpu::Context& context, uint32_t width, uint32_t height);

  uint32_t width, height;
  gpu::Image visibility;   // r32ui: the triangle seen at each pixel centre (raster)
  gpu::Image color;        // rgba16f: sharp shaded colour (HDR)
  gpu::Image specular;     // rgba16f: its specular part
  gpu::Image normalDepth;  // rgba32f: world normal, linear view depth (metres)
  // rg16f: where each pixel's surface was in the previous frame, in pixels from the pixel (for
  // the sky: where its direction was)
  gpu::Image motion;
  gpu::Image depth;         // d32: the raster depth buffer
  gpu::Image accumulation;  // rgba32f: progressive ray-traced sum, alpha = samples
  gpu::Image display;       // rgba8: tonemapped sRGB output
  gpu::Buffer readback;     // display's pixels for the CPU
};

}  // namespace hdof
