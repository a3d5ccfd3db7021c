// Post-process DoF (stage 2), the composite's tile lists: each tile goes to the list of the
// composite's full-resolution blurs when one of its pixels has a CoC in their range or, with a near
// field in reach, a small near blur within the tiles around it may spread over its pixels (the
// composite reads 2 pixels around each pixel); else to the list of tiles that need only the sharp
// colour and the half-resolution layers (shared/dof.h, DofTileLists). The lists' dispatch
// arguments start at zero workgroups (step dof_tile_lists_clear). One thread per tile.
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"

layout(set = 1, binding = 1, rgba16f) uniform readonly image2D tiles;
layout(set = 1, binding = 2, rg16f) uniform readonly image2D dilatedTiles;
layout(set = 1, binding = 3, std430) buffer TileLists {
  DofTileLists header;
  uint entries[];
} lists;

void main() {
  ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
  ivec2 count = imageSize(tiles);
  if (any(greaterThanEqual(tile, count))) return;
  bool smallBlur = imageLoad(tiles, tile).z > 0.0;
  if (imageLoad(dilatedTiles, tile).y <= -kDofFocusZone) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        ivec2 neighbour = clamp(tile + ivec2(dx, dy), ivec2(0), count - 1);
        smallBlur = smallBlur || imageLoad(tiles, neighbour).w > 0.0;
      }
    }
  }
  uint entry = uint(tile.x) | uint(tile.y) << 16u;
  if (smallBlur) {
    lists.entries[atomicAdd(lists.header.smallBlurGroupsX, 1u)] = entry;
  } else {
    uint last = uint(count.x * count.y) - 1u;
    lists.entries[last - atomicAdd(lists.header.layersGroupsX, 1u)] = entry;
  }
}
