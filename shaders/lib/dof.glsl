// Helpers of the post-process depth of field (stage 2, shaders/dof_*.comp), also used by the ray
// mask (stage 3). Needs lib/frame.glsl.
#ifndef HDOF_LIB_DOF_GLSL
#define HDOF_LIB_DOF_GLSL
#include "shared/dof.h"

float saturate(float x) { return clamp(x, 0.0, 1.0); }

// The larger and the smaller of two floats that are neither negative nor NaN, compared as signed
// integers, whose order their bits keep: on a CPU device a float max or min is three
// instructions (a NaN check and a blend after it), an integer one is one.
float maxOfPositive(float a, float b) {
  return intBitsToFloat(max(floatBitsToInt(a), floatBitsToInt(b)));
}
float minOfPositive(float a, float b) {
  return intBitsToFloat(min(floatBitsToInt(a), floatBitsToInt(b)));
}

float signedCoc(float linearDepth) {
  float coc = pixelCoc(linearDepth);
  return clamp(coc, -kDofMaxCoc, kDofMaxCoc);
}

// Whether a neighbour's CoC is that of a wide near-field blur in front of the pixel (own CoC): the
// blur spreads the neighbour's colour over the pixel, so any of it that the pixel holds sharp
// shows as an outline of the near object inside its blur.
bool wideNearBlurInFront(float neighbour, float own) {
  return neighbour <= -kDofHalfResCoc && neighbour < own - kDofFocusZone;
}

// CoC radius in half-resolution pixels. At least half a pixel: a pixel always covers itself,
// and 1 / (pi r^2) stays finite.
float halfResRadius(float coc) { return max(abs(coc) * 0.25, 0.5); }

// Bilateral weight between two CoCs: 1 when equal, 0 once they differ by half the reference
// (at least 2 px), so in-focus colour does not mix into blur nor near colour into far.
float cocSimilarity(float coc, float reference) {
  return saturate(1.0 - abs(coc - reference) / max(2.0, 0.5 * abs(reference)));
}

// How much of a pixel is the half-resolution blur rather than the full-resolution one.
float halfResAmount(float coc) {
  return saturate((abs(coc) - kDofSmallBlurCoc) / (kDofHalfResCoc - kDofSmallBlurCoc));
}

// How much a sample belongs to the half-resolution near layer, which may spread over sharper
// pixels; the composite spreads the smaller near blurs at full resolution.
float nearness(float coc) { return coc < 0.0 ? halfResAmount(coc) : 0.0; }

// The gather kernel of a tile whose dilated largest |CoC| is tileCoc: its ring count and ring
// spacing (half-resolution pixels). The prefilter fills the gaps between taps with the spacing.
int gatherRings(float tileCoc) {
  return clamp(int(ceil(tileCoc * 0.25 / kDofRingSpacing)), 1, kDofMaxRings);
}
float ringSpacing(float tileCoc) { return tileCoc * 0.25 / float(gatherRings(tileCoc)); }

// How far (pixels) to look for discs that may cover a pixel of a tile whose dilation found discs of
// up to this diameter: no farther than the dilation looks.
int searchRadius(float dilatedDiameter) {
  return min(int(ceil(0.5 * dilatedDiameter)), kDofTileReach * int(kDofTileSize));
}

// The tiles across and down the frame, as the tile images hold them (see halfImageSize).
ivec2 tileCount() { return (ivec2(frame.imageSize) + int(kDofTileSize) - 1) / int(kDofTileSize); }

// The dilated tile (x: largest |CoC|, y: nearest CoC) of a half-resolution pixel.
ivec2 tileOfHalfResPixel(ivec2 pixel) { return pixel / int(kDofTileSize / 2u); }

#endif
