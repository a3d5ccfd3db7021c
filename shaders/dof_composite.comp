// Post-process DoF (stage 2), composite of the tiles with full-resolution blurs (see
// lib/dof_composite.glsl): the sharp colour where the CoC is nothing (on a still view, under
// kDofSubPixelBlurCoc; in motion, a pixel); up to kDofSmallBlurCoc a full-resolution blur, with the
// small near blurs in front spread over it; beyond, the far layer, blended in as |CoC| grows; then
// the near layer over everything, with its opacity. One pipeline per list of such tiles
// (shared/dof.h): the narrow and wide lists' are made without the code their tiles never run.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require

#include "lib/dof_composite.glsl"

// The list of tiles this pipeline composites: kDofListNarrow, kDofListWide, kDofListNear,
// kDofListWider or kDofListNearWider.
layout(constant_id = 0) const uint kList = 4;  // kDofListNearWider: every blur
const bool kWideBlurs = kList != kDofListNarrow;
const bool kNearSpread = kList == kDofListNear || kList == kDofListNearWider;

// The small blurs below read kSmallBlurReach pixels around a pixel: discs up to a radius of
// kSmallBlurReach + 0.5, which no pixel beyond that reach overlaps (the CoC kDofWideCoc in the
// wide and near lists, kDofSmallBlurCoc in the wider ones).
const int kSmallBlurReach = kList == kDofListWider || kList == kDofListNearWider
                                ? int(0.5 * kDofSmallBlurCoc)
                                : int(0.5 * kDofWideCoc);
const int kWindow = 2 + 2 * kSmallBlurReach;

// The full-resolution colour and CoC of the pixels around a quad that the small blurs of its
// four pixels read.
vec3 windowColor[kWindow * kWindow];
float windowCoc[kWindow * kWindow];
float windowReach[kWindow * kWindow];  // how far each pixel's own blur reaches
float windowDensity[kWindow * kWindow];  // its energy per pixel of its disc

// wide: the whole window; else only the pixels next to the quad (all a sub-pixel blur reads).
void loadWindow(ivec2 first, bool wide) {
  ivec2 last = ivec2(frame.imageSize) - 1;
  [[unroll]] for (int j = 0; j < kWindow * kWindow; ++j) {
    ivec2 inWindow = ivec2(j % kWindow, j / kWindow);
    if (!wide && any(greaterThan(abs(2 * inWindow - (kWindow - 1)), ivec2(3)))) continue;
    ivec2 source = clamp(first + inWindow - kSmallBlurReach, ivec2(0), last);
    vec4 texel = imageLoad(colorCoc, source);
    windowColor[j] = texel.rgb;
    windowCoc[j] = texel.a;
    windowReach[j] = 0.5 * abs(windowCoc[j]);
    windowDensity[j] = 1.0 / max(kPi * windowReach[j] * windowReach[j], 1.0);
  }
}

// A lens's blur of radius r (under 1.5 px) over the raster's pixels: the weight of a side or
// diagonal neighbour relative to the pixel's own. Two kernels, for what the raster holds:
// - cells: the disc integrated over the pixel's area against its neighbours' (each side one
//   (2r/3 - r^2/4) / pi, each diagonal one r^2 / (8 pi), at most r = 1), right for a raster of one
//   sample per pixel, the first frame's;
// - disc: once the raster averages jittered samples over the pixel (a box filter, as the ray
//   tracers' rays do), the blur adds only the disc, whose variance is r^2 / 4 along an axis where
//   the cells' is r^2 / 4 + 1/6 (a wall at a 1.6 px CoC came out softer than the reference). Its
//   weights bring the kernel's frequency response closest to the disc's (2 J1(rw) / rw), weighed
//   by a natural image's power (1 / w^2) through the pixel's box (sinc^2 w/2): within 0.04 of the
//   least-squares fit every 0.1 px of radius.
// After the first frame the weights are the mean of the two: the raster's 16 samples still carry
// sampling noise on in-focus edges, which the wider kernel smooths (16 frames of `builtin:dof`,
// postprocess 38.52 dB, the disc's 38.38, the mean 38.66; edge band 35.57, 34.89, 35.59).
float subPixelDiscWeight(bool diagonal, float r) {
  float c = min(r, 1.0);
  float own = 1.0 - 8.0 * c / (3.0 * kPi) + c * c / (2.0 * kPi);
  float cells = (diagonal ? c * c / (8.0 * kPi) : (2.0 * c / 3.0 - 0.25 * c * c) / kPi) / own;
  float r2 = r * r, beyond = max(r - 0.85, 0.0);
  float disc = diagonal ? 1.3 * beyond * beyond * sqrt(beyond) : r2 * (0.2 + 0.1 * r2);
  return frame.rasterSample == 0u ? cells : 0.5 * (cells + disc);
}

// The blur of a pixel whose CoC is too small for the half-resolution layers (up to 5 px):
// a disc of its own diameter over the full-resolution colour, in which a tap counts as far as
// its own blur reaches the pixel, so that a sharper neighbour (an in-focus silhouette) does not
// spread into it. Below a pixel's width the sharp colour is exact. offset: the pixel in its quad.
// A near-field pixel is covered by its surface only as far as that surface's blur reaches it
// (scatter-as-gather: each tap's energy over its own disc); beside the surface's silhouette the
// rest is what lies behind it, seen through the blurred edge: the farther pixels around.
// subPixel: blurs under a pixel's width as well, and up to a 3 px CoC the weights of the pixels
// next to it from subPixelDiscWeight (with the smaller radius of the two: a sharper neighbour
// spreads no further than its own disc), handing over to the disc's edge ramp by a 3 px CoC. A
// neighbour brighter than the pixel counts less (as bright as the pixel at most), so that a
// raster highlight's sparkle does not spread a halo. wide: whether the window holds more than
// the pixels next to the quad.
vec3 smallBlur(ivec2 offset, float coc, vec3 sharp, bool subPixel, bool wide) {
  float radius = min(0.5 * abs(coc), float(kSmallBlurReach) + 0.5);
  if (radius < (subPixel ? 0.5 * kDofSubPixelBlurCoc : 0.5)) return sharp;
  vec4 sum = vec4(sharp, 1.0);
  vec4 behind = vec4(0.0);
  // The radius (px) from which the neighbours' weights hand over to the disc's edge ramp, done
  // by 1.5 px.
  float handOver = frame.rasterSample == 0u ? 1.0 : 1.2;
  float covered = 1.0 / max(kPi * radius * radius, 1.0);
  [[unroll]] for (int dy = -kSmallBlurReach; dy <= kSmallBlurReach; ++dy) {
    [[unroll]] for (int dx = -kSmallBlurReach; dx <= kSmallBlurReach; ++dx) {
      if (dx == 0 && dy == 0 || !wide && max(abs(dx), abs(dy)) > 1) continue;
      float distance = length(vec2(dx, dy));
      int j = (offset.y + dy + kSmallBlurReach) * kWindow + offset.x + dx + kSmallBlurReach;
      float inDisc = saturate(radius - distance + 0.5);
      float reaches = saturate(windowReach[j] - distance + 0.5);
      float weight = inDisc * reaches;
      // A near blur in front of the pixel spreads over it (smallNearSpread), not into its blur.
      float tapCoc = windowCoc[j];
      if (kNearSpread && tapCoc <= -kDofFocusZone && tapCoc <= coc - 0.25 * abs(tapCoc))
        weight = 0.0;
      if (subPixel && distance < 1.5) {
        float bothReach = min(radius, windowReach[j]);
        float lens = subPixelDiscWeight(distance > 1.0, min(bothReach, 1.5)) *
                     min(1.0, (1.0 + luminance(sharp)) / (1.0 + luminance(windowColor[j])));
        weight = mix(lens, weight, saturate((bothReach - handOver) / (1.5 - handOver)));
      }
      sum += vec4(windowColor[j], 1.0) * weight;
      // Behind a near pixel: empty unless its disc reaches the taps (a CoC of -1 px or less),
      // never in a narrow tile. A tap is behind once its CoC is 1 px or a quarter sharper (a
      // slope's neighbours differ by less); with half as sharp, a floor at -2.1 px behind a post
      // at -3.3 px counted as the post's own surface, and the post's blurred edge stayed opaque
      // (`builtin:dof` postprocess, 16 frames: occlusion region 28.18 -> 28.66 dB).
      if (kWideBlurs && coc < 0.0) {
        if (windowCoc[j] > coc + max(1.0, 0.25 * abs(coc)))
          behind += vec4(windowColor[j], 1.0) * inDisc;
        else
          covered += reaches * windowDensity[j];
      }
    }
  }
  vec3 surface = sum.rgb / sum.w;
  if (behind.w == 0.0) return surface;
  return mix(behind.rgb / behind.w, surface, saturate(covered));
}

// The near field's small blurs over this pixel, premultiplied: every blurred near pixel in front
// of it whose disc reaches it adds its energy (colour over its disc's area), as the half-resolution
// near layer does for the larger ones.
vec4 smallNearSpread(ivec2 offset, float coc) {
  vec4 sum = vec4(0.0);
  [[unroll]] for (int dy = -kSmallBlurReach; dy <= kSmallBlurReach; ++dy) {
    [[unroll]] for (int dx = -kSmallBlurReach; dx <= kSmallBlurReach; ++dx) {
      if (dx == 0 && dy == 0) continue;
      int j = (offset.y + dy + kSmallBlurReach) * kWindow + offset.x + dx + kSmallBlurReach;
      float tapCoc = windowCoc[j];
      float fullRes = 1.0 - halfResAmount(tapCoc);  // the share not in the near layer
      if (tapCoc > -kDofFocusZone || tapCoc > coc - 0.25 * abs(tapCoc) || fullRes == 0.0) continue;
      float energy = saturate(windowReach[j] - length(vec2(dx, dy)) + 0.5) * windowDensity[j];
      sum += vec4(windowColor[j], 1.0) * (energy * fullRes);
    }
  }
  float alpha = saturate(sum.w);
  return sum.w > 0.0 ? vec4(sum.rgb / sum.w * alpha, alpha) : vec4(0.0);
}

void main() {
  ivec2 quad = listedQuad(kList);
  ivec2 size = ivec2(frame.imageSize);
  // A narrow tile's |CoC| is under kDofNarrowCoc and no near field is in its reach: the
  // half-resolution layers show nowhere in it.
  CompositeQuad q = loadQuad(quad, kWideBlurs);
  // Blurs under a pixel's width on a still view (in motion, the reprojected anti-aliasing history
  // is already about that soft).
  bool subPixel = frame.previousViewProj == frame.viewProj;
  float minBlur = subPixel ? kDofSubPixelBlurCoc : 1.0;
  bool anySmallBlur = false;
  [[unroll]] for (int i = 0; i < 4; ++i)
    anySmallBlur = anySmallBlur || (abs(q.coc[i]) >= minBlur && q.blur[i] < 1.0);
  // Whether a small near blur may spread over the quad: the 3x3 half-resolution pixels cover the
  // 2 px around it, each with the nearest CoC of its 2x2 pixels; a wider list's blurs read
  // further, and their quads spread the near field in any case.
  bool anySmallNear = kSmallBlurReach > 2 && kNearSpread && q.withNear;
  if (kNearSpread && q.withNear) {
    [[unroll]] for (int j = 0; j < 9; ++j)
      anySmallNear = anySmallNear || (q.far[j].a <= -kDofFocusZone && q.far[j].a > -kDofHalfResCoc);
  }
  // Blurs that read past the pixels next to the quad: a radius from 1.5 px, a near-field pixel's
  // cover, the near spread.
  bool wide = anySmallNear;
  [[unroll]] for (int i = 0; i < 4; ++i)
    wide = wide || abs(q.coc[i]) >= kDofNarrowCoc || q.coc[i] <= kDofNarrowNearCoc;
  wide = kWideBlurs && wide;
  if (anySmallBlur || anySmallNear) loadWindow(q.first, wide);

  [[unroll]] for (int i = 0; i < 4; ++i) {
    ivec2 offset = ivec2(i & 1, i >> 1);
    ivec2 pixel = q.first + offset;
    if (any(greaterThanEqual(pixel, size))) continue;
    vec4 far, near;
    halfResLayers(q, i, far, near);
    vec3 behind = anySmallBlur && far.a < 1.0
                      ? smallBlur(offset, q.coc[i], q.sharp[i], subPixel, wide)
                      : q.sharp[i];
    vec3 background = overFarLayer(behind, far);
    if (anySmallNear) {
      vec4 smallNear = smallNearSpread(offset, q.coc[i]);
      background = background * (1.0 - smallNear.a) + smallNear.rgb;
    }
    storeComposite(pixel, background, near);
  }
}
