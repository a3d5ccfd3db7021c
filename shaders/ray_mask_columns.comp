// Ray mask (stage 3), spread along columns: the second half of the disc dilation (see
// ray_mask_spread.comp). A pixel is within an edge's disc when a pixel of its column reaches it,
// or when its tile is one that a disc wider than the tile dilation reaches (ray_mask_far.comp; the
// sharper side of such an edge taken to be the pixel's own CoC). Per pixel, the strongest of those
// edges (x; -1: none) and the smallest |CoC| of their sharper sides (y), which ray_mask_rays.comp
// turns into rays. Apart from the rays, which follow the variance of every frame's rays, so that
// it stands with the edges while the raster and the lens do.
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"
#include "lib/skippable.glsl"

layout(set = 1, binding = 1, rgba16f) uniform readonly image2D spread;
layout(set = 1, binding = 2, rg16f) uniform readonly image2D dilatedTiles;
layout(set = 1, binding = 3, r16f) uniform readonly image2D farTiles;
layout(set = 1, binding = 4, rgba32f) uniform readonly image2D normalDepth;
layout(set = 1, binding = 5) uniform writeonly image2D covered;  // rg16f

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(frame.imageSize);
  if (any(greaterThanEqual(pixel, size))) return;
  int radius = searchRadius(imageLoad(dilatedTiles, pixel / int(kDofTileSize)).x);
  bool nearEdge = false;
  float strongest = 0.0;
  float sharpest = kDofMaxCoc;
  for (int dy = max(-radius, -pixel.y); dy <= min(radius, size.y - 1 - pixel.y); ++dy) {
    vec3 row = imageLoad(spread, pixel + ivec2(0, dy)).xyz;
    if (row.x >= float(abs(dy))) {
      nearEdge = true;
      strongest = maxOfPositive(strongest, row.y);
      sharpest = minOfPositive(sharpest, row.z);
    }
  }
  // Most tiles are reached by no such disc.
  SKIPPABLE_IF(imageLoad(farTiles, pixel / int(kDofTileSize)).x > 0.0) {
    nearEdge = true;
    strongest = 1.0;
    sharpest = min(sharpest, abs(signedCoc(imageLoad(normalDepth, pixel).w)));
  }
  imageStore(covered, pixel, vec4(nearEdge ? strongest : -1.0, sharpest, 0.0, 0.0));
}
