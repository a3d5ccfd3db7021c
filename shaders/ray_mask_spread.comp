// Ray mask (stage 3), spread along rows: the first half of a separable dilation of every edge pixel
// by a disc of its own radius R (half its reach). A pixel p is within R of an edge pixel e exactly
// when |p.y - e.y| <= sqrt(R^2 - (p.x - e.x)^2), so each pixel keeps the largest such half height
// over the edge pixels of its row (x; -1: none), their strongest edge (y) and the smallest |CoC| of
// their sharper sides (z). The pixel's dilated tile bounds the search (all of an 8x8 workgroup lies
// in one tile, so the loop is uniform), as far as the tile dilation reaches: wider discs reach
// the tiles beyond as ray_mask_far.comp marks them.
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"

layout(set = 1, binding = 1, r16f) uniform readonly image2D reach;
layout(set = 1, binding = 2, rg16f) uniform readonly image2D strength;
layout(set = 1, binding = 3, rg16f) uniform readonly image2D dilatedTiles;
layout(set = 1, binding = 4, rgba16f) uniform writeonly image2D spread;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(frame.imageSize);
  if (any(greaterThanEqual(pixel, size))) return;
  int radius = searchRadius(imageLoad(dilatedTiles, pixel / int(kDofTileSize)).x);
  float halfHeight = -1.0;
  float strongest = 0.0;
  float sharpest = kDofMaxCoc;
  for (int dx = max(-radius, -pixel.x); dx <= min(radius, size.x - 1 - pixel.x); ++dx) {
    ivec2 source = pixel + ivec2(dx, 0);
    float edgeRadius = 0.5 * imageLoad(reach, source).x;
    float squared = edgeRadius * edgeRadius - float(dx * dx);
    if (edgeRadius > 0.0 && squared >= 0.0) {
      halfHeight = max(halfHeight, sqrt(squared));
      vec2 edge = imageLoad(strength, source).xy;
      strongest = maxOfPositive(strongest, edge.x);
      sharpest = minOfPositive(sharpest, edge.y);
    }
  }
  imageStore(spread, pixel, vec4(halfHeight, strongest, sharpest, 0.0));
}
