// Post-process DoF (stage 2), tiles: per tile of kDofTileSize pixels, the largest |CoC| and the
// nearest (most negative) CoC. One thread per tile: a workgroup-wide reduction with barriers costs
// more on a CPU device than these few loads. The ray mask (stage 3) runs it on its edges' reach
// too, as the step ray_mask_tiles.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"

layout(set = 1, binding = 1, r16f) uniform readonly image2D cocImage;
layout(set = 1, binding = 2, rg16f) uniform writeonly image2D tiles;

void main() {
  ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(tile, imageSize(tiles)))) return;
  ivec2 first = tile * int(kDofTileSize);
  ivec2 last = min(first + int(kDofTileSize), ivec2(frame.imageSize)) - 1;
  float largest = 0.0;
  float nearest = 0.0;
  for (int y = first.y; y <= last.y; ++y) {
    [[unroll]] for (int i = 0; i < int(kDofTileSize); ++i) {
      float coc = imageLoad(cocImage, ivec2(min(first.x + i, last.x), y)).r;
      largest = max(largest, abs(coc));
      nearest = min(nearest, coc);
    }
  }
  imageStore(tiles, tile, vec4(largest, nearest, 0.0, 0.0));
}
