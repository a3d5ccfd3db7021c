// Post-process DoF (stage 2), CoC and downsample: the signed CoC of every pixel beside its colour
// (full resolution, for the tiles and the composite), and colour and CoC at half resolution. The
// CoC of a 2x2 block is its nearest, so near silhouettes grow rather than shrink; colours are
// weighted by how close their CoC is to it, so in-focus colour does not bleed into the blur of a
// near object. A background pixel beside a sharper, nearer one (an in-focus silhouette) takes its
// |CoC| when smaller: the raster averages its samples over the pixel, so its colour holds some of
// the silhouette's, while its depth is one sample's; blurred as background it would spread the
// silhouette's colour around it (a halo). The background's blur stops a pixel short instead.
// Beside a wide near-field blur in front of it, a pixel holds some of that near surface's colour
// the same way, shown sharp under the blur: an outline of the near object inside its blur. Taken
// as a mix of the surface beside it and the pixel on its other side, it gives up the near
// surface's share, which the near blur spreads over it anyway.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"
#include "lib/skippable.glsl"

layout(set = 1, binding = 1, rgba16f) uniform readonly image2D color;
layout(set = 1, binding = 2, rgba32f) uniform readonly image2D normalDepth;
layout(set = 1, binding = 3, rgba16f) uniform writeonly image2D colorCoc;  // a: CoC
layout(set = 1, binding = 4, rgba16f) uniform writeonly image2D halfColorCoc;  // a: CoC

// The block's pixels in the 4x4 window around it, and the offsets in the window (and in the
// image) to a pixel's left, right, upper and lower neighbour.
const int kBlock[4] = int[4](5, 6, 9, 10);
const int kBeside[4] = int[4](-1, 1, -4, 4);
const ivec2 kBesideStep[4] = ivec2[4](ivec2(-1, 0), ivec2(1, 0), ivec2(0, -1), ivec2(0, 1));

// How much of a pixel's colour (own) is the near-field surface beside it (front) rather than what
// lies behind (back: the pixel on its other side), the pixel taken as their mix; none where the
// two are too alike to tell, or where the pixel's colour is not such a mix.
float frontShare(vec3 own, vec3 front, vec3 back) {
  vec3 across = front - back;
  float length2 = dot(across, across);
  if (length2 <= 0.01 * max(dot(front, front), dot(back, back))) return 0.0;
  float share = saturate(dot(own - back, across) / length2);
  vec3 off = own - back - share * across;
  return dot(off, off) <= 0.0625 * length2 ? share : 0.0;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, halfImageSize()))) return;
  ivec2 size = ivec2(frame.imageSize);
  // The CoCs of the 4x4 pixels around the block (its 2x2 and the pixels beside them; the
  // corners are not read).
  float around[16];
  [[unroll]] for (int j = 0; j < 16; ++j) {
    ivec2 inBlock = ivec2(j % 4, j / 4) - 1;
    if ((inBlock.x == -1 || inBlock.x == 2) && (inBlock.y == -1 || inBlock.y == 2)) continue;
    ivec2 source = clamp(pixel * 2 + inBlock, ivec2(0), size - 1);
    around[j] = signedCoc(imageLoad(normalDepth, source).w);
  }
  // The block's colours; beside a wide near-field blur in front of a pixel, its colour without the
  // near surface's share, which that blur spreads over it.
  vec3 colors[4];
  bool nearBeside = false;
  [[unroll]] for (int i = 0; i < 4; ++i) {
    colors[i] = imageLoad(color, min(pixel * 2 + ivec2(i & 1, i >> 1), size - 1)).rgb;
    int j = kBlock[i];
    [[unroll]] for (int k = 0; k < 4; ++k)
      nearBeside = nearBeside || wideNearBlurInFront(around[j + kBeside[k]], around[j]);
  }
  SKIPPABLE_IF(nearBeside) {
    [[unroll]] for (int i = 0; i < 4; ++i) {
      // The nearest such neighbour, and the pixel on the pixel's other side: only their two
      // colours are loaded (a load per lane, where any lane has such a neighbour).
      int j = kBlock[i];
      float nearestInFront = around[j];
      ivec2 toFront = ivec2(0);
      [[unroll]] for (int k = 0; k < 4; ++k) {
        float other = around[j + kBeside[k]];
        bool nearer = wideNearBlurInFront(other, around[j]) && other < nearestInFront;
        nearestInFront = nearer ? other : nearestInFront;
        toFront = nearer ? kBesideStep[k] : toFront;
      }
      if (nearestInFront < around[j]) {
        ivec2 source = pixel * 2 + ivec2(i & 1, i >> 1);
        vec3 front = imageLoad(color, clamp(source + toFront, ivec2(0), size - 1)).rgb;
        vec3 back = imageLoad(color, clamp(source - toFront, ivec2(0), size - 1)).rgb;
        colors[i] = max(colors[i] + frontShare(colors[i], front, back) * (back - front), 0.0);
      }
    }
  }
  float cocs[4];
  float nearest = kDofMaxCoc;
  [[unroll]] for (int i = 0; i < 4; ++i) {
    ivec2 source = pixel * 2 + ivec2(i & 1, i >> 1);
    int j = kBlock[i];
    float coc = around[j];
    float sharpest = abs(coc);
    [[unroll]] for (int k = 0; k < 4; ++k) {
      float other = around[j + kBeside[k]];
      if (other < coc) sharpest = min(sharpest, abs(other));
    }
    cocs[i] = sign(coc) * sharpest;
    if (all(lessThan(source, size))) imageStore(colorCoc, source, vec4(colors[i], cocs[i]));
    nearest = min(nearest, cocs[i]);
  }
  vec4 sum = vec4(0.0);
  [[unroll]] for (int i = 0; i < 4; ++i)
    sum += vec4(colors[i], 1.0) * cocSimilarity(cocs[i], nearest);
  imageStore(halfColorCoc, pixel, vec4(sum.rgb / sum.w, nearest));
}
