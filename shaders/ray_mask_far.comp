// Ray mask (stage 3), the discs wider than the tile dilation reaches (kDofTileReach tiles; up to
// kRayMaskFarReach): a near object close to the lens blurs over more of the image than the
// post-process renders. The same separable disc dilation as ray_mask_spread.comp and
// ray_mask_rays.comp, one texel per tile, with each tile's largest disc (the ray mask tiles' x)
// standing anywhere in its tile: the distance between two tiles is that between their nearest
// pixels. kColumns false: along rows, each tile keeps the largest half height (pixels) of such a
// disc over it (-1: none); true: along columns, 1 where a disc covers some pixel of the tile, else
// 0. ray_mask_rays.comp gives such a tile's pixels rays.
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"
#include "shared/ray_work.h"

layout(constant_id = 0) const bool kColumns = false;

// Rows: the ray mask tiles (x: the largest disc diameter); columns: the row pass.
layout(set = 1, binding = 1) uniform sampler2D source;  // any float format
layout(set = 1, binding = 2, r16f) uniform writeonly image2D result;

const int kFarTiles = int(ceil(0.5 * kRayMaskFarReach / float(kDofTileSize)));

void main() {
  ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
  ivec2 count = tileCount();
  if (any(greaterThanEqual(tile, count))) return;
  ivec2 step = kColumns ? ivec2(0, 1) : ivec2(1, 0);
  float found = kColumns ? 0.0 : -1.0;
  for (int d = -kFarTiles; d <= kFarTiles; ++d) {
    ivec2 other = tile + d * step;
    if (any(lessThan(other, ivec2(0))) || any(greaterThanEqual(other, count))) continue;
    float gap = float(max(abs(d) - 1, 0) * int(kDofTileSize));
    float value = texelFetch(source, other, 0).x;
    if (kColumns) {
      if (value >= gap) found = 1.0;
    } else {
      // Only discs wider than the tile dilation sees.
      float radius = 0.5 * value;
      if (radius > float(kDofTileReach * int(kDofTileSize)) && radius >= gap)
        found = max(found, sqrt(radius * radius - gap * gap));
    }
  }
  imageStore(result, tile, vec4(found));
}
