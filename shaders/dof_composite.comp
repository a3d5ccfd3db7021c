// Post-process DoF (stage 2), composite (full resolution): in the focus zone the sharp colour
// exactly; up to kDofSmallBlurCoc a full-resolution blur, with the small near blurs in front
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

// The full-resolution colour and CoC of the pixels around a quad that the small blurs of its
// four pixels read.
vec3 windowColor[kWindow * kWindow];
float windowCoc[kWindow * kWindow];
float windowReach[kWindow * kWindow];  // how far each pixel's own blur reaches
float windowDensity[kWindow * kWindow];  // its energy per pixel of its disc

void loadWindow(ivec2 first) {
  ivec2 last = ivec2(frame.imageSize) - 1;
  [[unroll]] for (int j = 0; j < kWindow * kWindow; ++j) {
    ivec2 source = clamp(first + ivec2(j % kWindow, j / kWindow) - kSmallBlurReach, ivec2(0), last);
    windowColor[j] = imageLoad(color, source).rgb;
    windowCoc[j] = imageLoad(cocImage, source).r;
    windowReach[j] = 0.5 * abs(windowCoc[j]);
    windowDensity[j] = 1.0 / max(kPi * windowReach[j] * windowReach[j], 1.0);
  }
}

// The blur of a pixel whose CoC is too small for the half-resolution layers (up to 5 px):
// a disc of its own diameter over the full-resolution colour, in which a tap counts as far as
// its own blur reaches the pixel, so that a sharper neighbour (an in-focus silhouette) does not
// spread into it. Below a pixel's width the sharp colour is exact. offset: the pixel in its quad.
// A near-field pixel is covered by its surface only as far as that surface's blur reaches it
// (scatter-as-gather: each tap's energy over its own disc); beside the surface's silhouette the
// rest is what lies behind it, seen through the blurred edge: the farther pixels around.
vec3 smallBlur(ivec2 offset, float coc, vec3 sharp) {
  float radius = min(0.5 * abs(coc), kSmallBlurRadius);
  if (radius < 0.5) return sharp;
  vec4 sum = vec4(sharp, 1.0);
  vec4 behind = vec4(0.0);
  float covered = 1.0 / max(kPi * radius * radius, 1.0);
  [[unroll]] for (int dy = -kSmallBlurReach; dy <= kSmallBlurReach; ++dy) {
    [[unroll]] for (int dx = -kSmallBlurReach; dx <= kSmallBlurReach; ++dx) {
      if (dx == 0 && dy == 0) continue;
      float distance = length(vec2(dx, dy));
      int j = (offset.y + dy + kSmallBlurReach) * kWindow + offset.x + dx + kSmallBlurReach;
      float inDisc = saturate(radius - distance + 0.5);
      float reaches = saturate(windowReach[j] - distance + 0.5);
      sum += vec4(windowColor[j], 1.0) * (inDisc * reaches);
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
  bool anySmallBlur = false;
  [[unroll]] for (int i = 0; i < 4; ++i)
    anySmallBlur = anySmallBlur || (abs(coc[i]) >= 1.0 && blur[i] < 1.0);

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
  if (anySmallBlur || anySmallNear) loadWindow(first);

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
    vec3 near = anySmallBlur && farAmount < 1.0 ? smallBlur(offset, coc[i], sharp[i]) : sharp[i];
    vec3 background = farAmount > 0.0 ? mix(near, farSum.rgb / farSum.w, farAmount) : near;
    if (anySmallNear) {
      vec4 smallNear = smallNearSpread(offset, coc[i]);
      background = background * (1.0 - smallNear.a) + smallNear.rgb;
    }
    imageStore(result, pixel, vec4(background * (1.0 - nearSum.a) + nearSum.rgb, 1.0));
  }
}
