// Post-process DoF (stage 2), the composite's tile lists (shared/dof.h, DofTileLists): a tile
// goes to a list of the full-resolution blurs when one of its pixels has a CoC in their range or,
// with a near field in reach, a small near blur within the tiles around it may spread over its
// pixels (the composite reads 2 or 3 pixels around each pixel): the near list when a near field is
// in reach, else the wide or the narrow list by its largest and nearest CoC, and the near-wider or
// wider list instead of the near or wide one when such a blur is kDofWideCoc or more; else to the
// list of tiles that need only the sharp colour and the half-resolution layers. The lists'
// dispatch arguments start at zero workgroups (step dof_tile_lists_clear). One thread per tile.
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
  ivec2 count = tileCount();
  if (any(greaterThanEqual(tile, count))) return;
  vec4 own = imageLoad(tiles, tile);  // largest |CoC|, nearest CoC, small blur, small near
  float smallBlur = own.z;  // 0: none, 1: under kDofWideCoc, 2: wider
  bool nearInReach = imageLoad(dilatedTiles, tile).y <= -kDofFocusZone;
  if (nearInReach) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        ivec2 neighbour = clamp(tile + ivec2(dx, dy), ivec2(0), count - 1);
        smallBlur = max(smallBlur, imageLoad(tiles, neighbour).w);
      }
    }
  }
  bool narrow = own.x < kDofNarrowCoc && own.y > kDofNarrowNearCoc;
  bool wider = smallBlur > 1.0;
  uint list = smallBlur == 0.0 ? kDofListLayers
              : nearInReach    ? (wider ? kDofListNearWider : kDofListNear)
              : narrow         ? kDofListNarrow
              : wider          ? kDofListWider
                               : kDofListWide;
  uint first = list * uint(count.x * count.y);
  lists.entries[first + atomicAdd(lists.header.lists[list].groupsX, 1u)] =
      uint(tile.x) | uint(tile.y) << 16u;
}
