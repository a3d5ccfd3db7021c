// Spatial reconstruction of the hybrid's ray-traced layers (stage 6, after the temporal
// accumulation, as in the paper): each traced pixel gathers its traced neighbours over a disc of an
// eighth of its circle of confusion (the average near and far CoC blended by the accumulated hit
// ratio), rejecting neighbours whose own CoC is smaller than their distance (their blur does not
// reach this pixel), and weighting them by how far their luminance lies from this pixel's in units
// of the noise left in its average (the clamped variance of its rays over the rays accumulated): a
// young, noisy pixel borrows from its neighbours, a converged one keeps its own colour. The traced
// colour is already the lens's blur of the scene, so it changes across the CoC: a disc of half the
// CoC blurred it a second time (a biased edge that more rays never removed), an eighth of it holds
// a pixel's blur the same while still denoising wide blurs. While a pixel's history is short, its
// own CoC is a few rays' chance (youngNearCoc): it gathers at least as far as the near blur its
// neighbourhood's rays met reaches it. For the composite's noise test it also writes how far the
// reconstructed colour lies from the post-process's and the noise left in it. One thread per pixel
// of the ray mask's work list.
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"
#include "lib/sampling.glsl"
#include "shared/ray_work.h"
#include "lib/skippable.glsl"

HDOF_RAY_WORK_LIST(1, readonly);
layout(set = 1, binding = 2, r8ui) uniform readonly uimage2D rays;  // rays traced this frame
layout(set = 1, binding = 3, rg16f) uniform readonly image2D layerCoc;  // near |CoC|, far CoC
// Near: colour x ratio, ratio; far: colour x (1 - ratio), rays; moments: m1, m2, rays, depth.
layout(set = 1, binding = 4, rgba32f) uniform readonly image2D historyNear;
layout(set = 1, binding = 5, rgba32f) uniform readonly image2D historyFar;
layout(set = 1, binding = 6, rgba32f) uniform readonly image2D historyMoments;
layout(set = 1, binding = 7, rg16f) uniform readonly image2D variance;  // of one ray, rays
layout(set = 1, binding = 8) uniform writeonly image2D outNear;
layout(set = 1, binding = 9) uniform writeonly image2D outFar;
layout(set = 1, binding = 10, rgba16f) uniform readonly image2D postProcess;  // its colour, HDR
// rg16f: for the composite's noise test (hybrid_composite.comp: tracedBeyondNoise), how far the
// reconstructed colour lies from the post-process's (its largest channel) and the noise left in it
// (a standard deviation: the variance of the rays it averages, the pixel's times the effective
// count of the gather's weights, scaled by kNoiseTestShare); 0 where the variance is not measured
// (a short history, and in motion or a focus pull), and negative where it cannot bound the
// pixel's own error, which leaves the pixel to the count of its rays: a variance of fewer than
// kNoiseTestFrames frames of its rays, or rays whose luminance is a few rare bright hits (a
// light's blur: fewer than kNoiseTestBrightHits such hits, n L^2 / variance).
layout(set = 1, binding = 11) uniform writeonly image2D outDifference;
// Per tile, the near-field blurs in reach: the post-process's dilated tiles (y: the nearest CoC
// whose blur can reach the tile) and the ray mask's tiles of near blurs wider than it renders.
layout(set = 1, binding = 12, rg16f) uniform readonly image2D dilatedTiles;
layout(set = 1, binding = 13, r16f) uniform readonly image2D farTiles;

const int kTaps = 6;  // pairs of taps
const float kMaxRadius = 8.0;  // pixels: the gather denoises, the blur itself is traced
const float kVarianceMin = 1e-4, kVarianceMax = 1.0;
const float kLuminanceSigmas = 2.0;

// The diameter of the pixel's blur: its layers' CoCs weighted by its hit ratio.
float blendedCoc(ivec2 pixel, float ratio) {
  vec2 coc = imageLoad(layerCoc, pixel).xy;
  return mix(abs(coc.y), coc.x, ratio);
}

// How far a near-field blur reaches a pixel whose history is short: the widest near CoC that the
// rays of its 3x3 neighbourhood met this frame, times the share of their rays that met the near
// field. Such a pixel's own hit ratio is a few rays' coin flips: inside a wide near blur, a pixel
// whose one ray passed the near surface had the background's small CoC, so that it gathered
// nothing and no neighbour took it in, and the blur came out peppered with single pixels of the
// background's colour; at the blur's rim, where most rays pass, the share keeps the background
// sharp.
float youngNearCoc(ivec2 pixel) {
  ivec2 last = ivec2(frame.imageSize) - 1;
  float widest = 0.0, ratioSum = 0.0, traced = 0.0;
  for (int i = 0; i < 9; ++i) {
    ivec2 q = clamp(pixel + ivec2(i % 3 - 1, i / 3 - 1), ivec2(0), last);
    if (imageLoad(rays, q).r == 0u) continue;
    widest = max(widest, imageLoad(layerCoc, q).x);
    ratioSum += imageLoad(historyNear, q).a;
    traced += 1.0;
  }
  return widest * ratioSum / max(traced, 1.0);
}

// Whether a near-field blur wide enough for the gather to reach a neighbour (an eighth of it,
// kHybridSpatialRadiusOfCoc, a pixel or more) can cover the pixel: only then can youngNearCoc
// widen its disc. Near surfaces out of the image, which only rays see, are in no tile; their
// rays are shown by their count alone (hybrid_composite.comp), a young pixel's by a few of the
// kHybridTrustedRays.
bool gatherableNearBlurInReach(ivec2 pixel) {
  ivec2 tile = pixel / int(kDofTileSize);
  return imageLoad(dilatedTiles, tile).y <= -1.0 / kHybridSpatialRadiusOfCoc ||
         imageLoad(farTiles, tile).x > 0.0;
}

void main() {
  if (gl_GlobalInvocationID.x >= workList.header.count) return;
  uvec2 entry = workList.entries[gl_GlobalInvocationID.x];
  ivec2 pixel = ivec2(unpackRayWorkPixel(entry.x));
  vec4 near = imageLoad(historyNear, pixel);
  vec4 far = imageLoad(historyFar, pixel);
  float lum = luminance(near.rgb + far.rgb);
  float samples = max(imageLoad(historyMoments, pixel).z, 1.0);
  float rayVariance = imageLoad(variance, pixel).r;
  float noise = sqrt(clamp(rayVariance, kVarianceMin, kVarianceMax) / samples);
  float nearReach = 0.0;
  SKIPPABLE_IF(rayVariance >= kRayMaskVarianceNew && gatherableNearBlurInReach(pixel)) {
    nearReach = youngNearCoc(pixel);
  }
  float radius =
      min(kHybridSpatialRadiusOfCoc * max(blendedCoc(pixel, near.a), nearReach), kMaxRadius);

  vec4 nearSum = near, farSum = far;
  float weightSum = 1.0, weightSquares = 1.0;
  ivec2 size = ivec2(frame.imageSize);
  float turn = toUnitFloat(pcgHash(uint(pixel.x) * 7919u + uint(pixel.y) * 104729u));
  // No taps under a pixel's radius. A bound rather than a branch: a device that runs both sides
  // of a branch under a mask (lavapipe) still leaves a loop that no lane enters.
  int taps = radius >= 1.0 ? kTaps : 0;
  for (int i = 0; i < taps; ++i) {
    // A Vogel spiral over the half disc, turned per pixel so that no pattern shows, and each
    // tap's mirror through the pixel: the pair is weighted by how far its mean lies from this
    // pixel's luminance, so that across a smooth gradient of the blur (a ramp, whose pairs average
    // to the pixel) the neighbours on its brighter and darker side count alike. Weighted one by
    // one, the taps on the ramp's flatter side won at its foot and shoulder, which came out too
    // sharp by up to a few levels, more so as the noise fell.
    float r = radius * sqrt((float(i) + 0.5) / float(taps));
    float angle = kPi * (float(i) * 0.618034 + turn);
    ivec2 offset = ivec2(round(r * vec2(cos(angle), sin(angle))));
    vec4 pairNear = vec4(0.0), pairFar = vec4(0.0);
    float pairLum = 0.0, pairTaps = 0.0;
    for (int side = -1; side <= 1; side += 2) {
      ivec2 q = pixel + side * offset;
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
      if (imageLoad(rays, q).r == 0u) continue;
      vec4 qNear = imageLoad(historyNear, q);
      if (0.5 * max(blendedCoc(q, qNear.a), nearReach) < distance(vec2(q), vec2(pixel))) continue;
      vec4 qFar = imageLoad(historyFar, q);
      pairNear += qNear;
      pairFar += qFar;
      pairLum += luminance(qNear.rgb + qFar.rgb);
      pairTaps += 1.0;
    }
    if (pairTaps == 0.0) continue;
    float w = exp(-abs(pairLum / pairTaps - lum) / (kLuminanceSigmas * noise));
    nearSum += w * pairNear;
    farSum += w * pairFar;
    weightSum += w * pairTaps;
    weightSquares += w * w * pairTaps;
  }
  vec4 outNearValue = nearSum / weightSum;
  vec3 outFarColor = farSum.rgb / weightSum;
  imageStore(outNear, pixel, outNearValue);
  imageStore(outFar, pixel, vec4(outFarColor, far.a));

  vec3 shown = outNearValue.rgb + outFarColor;
  vec3 difference = abs(shown - imageLoad(postProcess, pixel).rgb);
  float spread = 0.0;
  if (frame.stillFrames > 0u && rayVariance < kRayMaskVarianceNew) {
    float gain = weightSum * weightSum / weightSquares;
    // Above 0 (a half float's smallest steps): 0 is a pixel without a measured noise.
    spread = max(kNoiseTestShare * sqrt(rayVariance / (far.a * gain)), 1e-6);
    float shownLum = luminance(shown);
    if (far.a < kNoiseTestFrames * float(entry.y) ||
        rayVariance * kNoiseTestBrightHits > far.a * shownLum * shownLum)
      spread = -spread;
  }
  imageStore(outDifference,
             pixel, vec4(max(max(difference.r, difference.g), difference.b), spread, 0.0, 0.0));
}
