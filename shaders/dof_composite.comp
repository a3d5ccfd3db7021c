// Post-process DoF (stage 2), composite (full resolution): the sharp colour where the CoC is
// nothing (on a still view, under kSubPixelBlurCoc; in motion, a pixel); up to kDofSmallBlurCoc a full-resolution blur, with the small near blurs in front
// spread over it; beyond, the far layer, blended in as |CoC| grows; then the near layer over
// everything, with its opacity (over in-focus pixels too: the blurred silhouette of a near object
// spreads).
// Each invocation does a 2x2 quad of pixels, whose bilinear footprints share the 3x3
// half-resolution pixels around it: 9 loads per layer instead of 16.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"

layout(set = 1, binding = 1, rgba16f) uniform readonly image2D color;
layout(set = 1, binding = 2, r16f) uniform readonly image2D cocImage;
layout(set = 1, binding = 3, rgba16f) uniform readonly image2D farLayer;  // a: CoC
layout(set = 1, binding = 4, rgba16f) uniform readonly image2D nearLayer;  // premultiplied
layout(set = 1, binding = 5, rg16f) uniform readonly image2D dilatedTiles;
layout(set = 1, binding = 6, rgba16f) uniform writeonly image2D result;

// The small blurs below read kSmallBlurReach pixels around a pixel: discs up to a radius of
// kSmallBlurReach + 0.5 (the CoC kDofSmallBlurCoc), which no pixel beyond that reach overlaps.
const int kSmallBlurReach = int(0.5 * kDofSmallBlurCoc);
const float kSmallBlurRadius = float(kSmallBlurReach) + 0.5;
const int kWindow = 2 + 2 * kSmallBlurReach;
// The smallest CoC blurred on a still view (px); below it the sharp colour is within 3%.
const float kSubPixelBlurCoc = 0.1;

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
    windowColor[j] = imageLoad(color, source).rgb;
    windowCoc[j] = imageLoad(cocImage, source).r;
    windowReach[j] = 0.5 * abs(windowCoc[j]);
    windowDensity[j] = 1.0 / max(kPi * windowReach[j] * windowReach[j], 1.0);
  }
}

// A lens's blur below a pixel is not nothing: a disc of radius r (< 1 px) over the raster's
// pixel-sized samples gives each side neighbour of a pixel (2r/3 - r^2/4) / pi of its weight,
// each diagonal one r^2 / (8 pi), the pixel itself the rest (the disc integrated over the pixel's
// area against its neighbours'): at a 1 px CoC the pixel keeps only 62%. This is that weight
// relative to the pixel's own.
float subPixelDiscWeight(bool diagonal, float r) {
  float own = 1.0 - 8.0 * r / (3.0 * kPi) + r * r / (2.0 * kPi);
  float neighbour = diagonal ? r * r / (8.0 * kPi) : (2.0 * r / 3.0 - 0.25 * r * r) / kPi;
  return neighbour / own;
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
  float radius = min(0.5 * abs(coc), kSmallBlurRadius);
  if (radius < (subPixel ? 0.5 * kSubPixelBlurCoc : 0.5)) return sharp;
  vec4 sum = vec4(sharp, 1.0);
  vec4 behind = vec4(0.0);
  float covered = 1.0 / max(kPi * radius * radius, 1.0);
  [[unroll]] for (int dy = -kSmallBlurReach; dy <= kSmallBlurReach; ++dy) {
    [[unroll]] for (int dx = -kSmallBlurReach; dx <= kSmallBlurReach; ++dx) {
      if (dx == 0 && dy == 0 || !wide && max(abs(dx), abs(dy)) > 1) continue;
      float distance = length(vec2(dx, dy));
      int j = (offset.y + dy + kSmallBlurReach) * kWindow + offset.x + dx + kSmallBlurReach;
      float inDisc = saturate(radius - distance + 0.5);
      float reaches = saturate(windowReach[j] - distance + 0.5);
      float weight = inDisc * reaches;
      if (subPixel && distance < 1.5) {
        float bothReach = min(radius, windowReach[j]);
        float lens = subPixelDiscWeight(distance > 1.0, min(bothReach, 1.0)) *
                     min(1.0, (1.0 + luminance(sharp)) / (1.0 + luminance(windowColor[j])));
        weight = mix(lens, weight, saturate((bothReach - 1.0) * 2.0));
      }
      sum += vec4(windowColor[j], 1.0) * weight;
      if (coc < 0.0) {
        if (windowCoc[j] > 0.5 * coc)
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
  ivec2 quad = ivec2(gl_GlobalInvocationID.xy);
  ivec2 first = quad * 2;
  ivec2 size = ivec2(frame.imageSize);
  if (any(greaterThanEqual(first, size))) return;
  vec3 sharp[4];
  float coc[4];
  float blur[4];
  bool anyBlur = false;
  [[unroll]] for (int i = 0; i < 4; ++i) {
    ivec2 pixel = min(first + ivec2(i & 1, i >> 1), size - 1);
    sharp[i] = imageLoad(color, pixel).rgb;
    coc[i] = imageLoad(cocImage, pixel).r;
    blur[i] = halfResAmount(coc[i]);
    anyBlur = anyBlur || blur[i] > 0.0;
  }
  bool withNear = imageLoad(dilatedTiles, first / int(kDofTileSize)).y <= -kDofFocusZone;
  // Blurs under a pixel's width on a still view (in motion, the reprojected anti-aliasing history
  // is already about that soft).
  bool subPixel = frame.previousViewProj == frame.viewProj;
  float minBlur = subPixel ? kSubPixelBlurCoc : 1.0;
  bool anySmallBlur = false;
  [[unroll]] for (int i = 0; i < 4; ++i)
    anySmallBlur = anySmallBlur || (abs(coc[i]) >= minBlur && blur[i] < 1.0);

  vec4 far[9];
  vec4 near[9];
  if (anyBlur || withNear) {
    ivec2 halfLast = imageSize(farLayer) - 1;
    [[unroll]] for (int j = 0; j < 9; ++j) {
      ivec2 source = clamp(quad + ivec2(j % 3 - 1, j / 3 - 1), ivec2(0), halfLast);
      far[j] = imageLoad(farLayer, source);
      if (withNear) near[j] = imageLoad(nearLayer, source);
    }
  }
  // Whether a small near blur may spread over the quad: the 3x3 half-resolution pixels cover the
  // small blurs' window, each with the nearest CoC of its 2x2 pixels.
  bool anySmallNear = false;
  if (withNear) {
    [[unroll]] for (int j = 0; j < 9; ++j)
      anySmallNear = anySmallNear || (far[j].a <= -kDofFocusZone && far[j].a > -kDofHalfResCoc);
  }
  // Blurs that read past the pixels next to the quad: a radius from 1.5 px, a near-field pixel's
  // cover, the near spread.
  bool wide = anySmallNear;
  [[unroll]] for (int i = 0; i < 4; ++i) wide = wide || abs(coc[i]) >= 3.0 || coc[i] <= -1.0;
  if (anySmallBlur || anySmallNear) loadWindow(first, wide);

  [[unroll]] for (int i = 0; i < 4; ++i) {
    ivec2 offset = ivec2(i & 1, i >> 1);
    ivec2 pixel = first + offset;
    if (any(greaterThanEqual(pixel, size))) continue;
    // A pixel centre lies a quarter of a half-resolution pixel inside the 2x2 half-resolution
    // pixels from offset to offset + 1 of the 3x3: bilinear weights 3/4 and 1/4.
    vec4 farSum = vec4(0.0);
    vec4 nearSum = vec4(0.0);
    [[unroll]] for (int k = 0; k < 4; ++k) {
      ivec2 corner = ivec2(k & 1, k >> 1);
      int j = (offset.y + corner.y) * 3 + offset.x + corner.x;
      vec2 axes = mix(vec2(0.75), vec2(0.25), equal(corner, offset));
      float bilinear = axes.x * axes.y;
      if (anyBlur) {
        // Far colour only from half-resolution pixels of a similar CoC, so it neither brings
        // sharp colour into the blur nor blur across a depth edge.
        float weight = bilinear * cocSimilarity(far[j].a, coc[i]);
        farSum += vec4(far[j].rgb, 1.0) * weight;
      }
      if (withNear) nearSum += near[j] * bilinear;
    }
    // Where no half-resolution pixel nearby has this pixel's CoC (a thin gap between in-focus
    // objects, which the downsample's nearest CoC closes), the sharp colour stands in.
    float farAmount = blur[i] * saturate(farSum.w * 4.0);
    vec3 near = anySmallBlur && farAmount < 1.0
                    ? smallBlur(offset, coc[i], sharp[i], subPixel, wide)
                    : sharp[i];
    vec3 background = farAmount > 0.0 ? mix(near, farSum.rgb / farSum.w, farAmount) : near;
    if (anySmallNear) {
      vec4 smallNear = smallNearSpread(offset, coc[i]);
      background = background * (1.0 - smallNear.a) + smallNear.rgb;
    }
    imageStore(result, pixel, vec4(background * (1.0 - nearSum.a) + nearSum.rgb, 1.0));
  }
}
