// Post-process DoF (stage 2), tiles: per tile of kDofTileSize pixels, the largest |CoC| and the
// nearest (most negative) CoC, and for the composite's tile lists (dof_tile_lists.comp) whether a
// pixel's |CoC| is in the range of the composite's full-resolution blurs (z) and whether a pixel
// has a small near-field blur (w): 0 for none, 1 for blurs under kDofWideCoc alone, 2 for wider
// ones. One thread per tile: a workgroup-wide reduction with barriers costs more on a CPU device
// than these few loads. The ray mask (stage 3) runs it on its edges' reach too, as the step
// ray_mask_tiles (x alone).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"

layout(set = 1, binding = 1) uniform sampler2D cocImage;  // any float format

layout(push_constant) uniform Push {
  uint channel;  // the channel of cocImage that holds the CoC
} push;
layout(set = 1, binding = 2, rgba16f) uniform writeonly image2D tiles;

void main() {
  ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(tile, tileCount()))) return;
  ivec2 first = tile * int(kDofTileSize);
  ivec2 last = min(first + int(kDofTileSize), ivec2(frame.imageSize)) - 1;
  float largest = 0.0;
  float nearest = 0.0;
  float smallBlur = 0.0, smallNear = 0.0;
  for (int y = first.y; y <= last.y; ++y) {
    [[unroll]] for (int i = 0; i < int(kDofTileSize); ++i) {
      float coc = texelFetch(cocImage, ivec2(min(first.x + i, last.x), y), 0)[push.channel];
      largest = max(largest, abs(coc));
      nearest = min(nearest, coc);
      float reach = abs(coc) < kDofWideCoc ? 1.0 : 2.0;
      if (abs(coc) >= kDofSubPixelBlurCoc && abs(coc) < kDofHalfResCoc)
        smallBlur = max(smallBlur, reach);
      if (coc <= -kDofFocusZone && coc > -kDofHalfResCoc) smallNear = max(smallNear, reach);
    }
  }
  imageStore(tiles, tile, vec4(largest, nearest, smallBlur, smallNear));
}
