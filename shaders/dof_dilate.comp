// Post-process DoF (stage 2), tile dilation: each tile takes the largest |CoC| and the nearest CoC
// of the tiles around it whose blur reaches it, so a gather sized by its tile sees every pixel that
// scatters onto it (kDofTileReach tiles cover the largest CoC radius). The ray mask (stage 3) runs
// it on its edges' reach too, as the step ray_mask_dilate.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"

layout(set = 1, binding = 1, rgba16f) uniform readonly image2D tiles;
layout(set = 1, binding = 2, rg16f) uniform writeonly image2D dilated;

void main() {
  ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
  ivec2 count = tileCount();
  if (any(greaterThanEqual(tile, count))) return;
  float largest = 0.0;
  float nearest = 0.0;
  [[unroll]] for (int dy = -kDofTileReach; dy <= kDofTileReach; ++dy) {
    [[unroll]] for (int dx = -kDofTileReach; dx <= kDofTileReach; ++dx) {
      ivec2 neighbour = tile + ivec2(dx, dy);
      if (any(lessThan(neighbour, ivec2(0))) || any(greaterThanEqual(neighbour, count))) continue;
      vec2 value = imageLoad(tiles, neighbour).xy;
      // The shortest distance between a pixel of this tile and one of the neighbour.
      float gap = length(vec2(max(abs(ivec2(dx, dy)) - 1, 0))) * float(kDofTileSize);
      if (value.x * 0.5 >= gap) largest = max(largest, value.x);
      if (-value.y * 0.5 >= gap) nearest = min(nearest, value.y);
    }
  }
  imageStore(dilated, tile, vec4(largest, nearest, 0.0, 0.0));
}
