// G-buffer (stage 1), anti-aliasing step: the raster's colour accumulated over frames. While the
// view rests every frame adds samples at other sub-pixel positions (a Halton sequence; the first
// kMultisampledFrames frames four where a pixel's samples see several triangles), and the running
// average, weighted by what each frame's sample counts for, converges to a supersampled image (a
// box filter over the pixel, as the ray tracers' jittered rays) over kStillRasterFrames frames,
// after which the step no longer runs. When the view moves, each frame samples another jittered
// position and the history is reprojected by the motion of the nearest surface around the pixel,
// clamped to the range of this frame's 3x3 neighbourhood (no ghosting where the surface changed)
// and blended in, so that edges stay smooth in motion where the picture allows it.
// The first frame after a cut, one sample per pixel with no history, smooths its edges spatially
// (spatialAntialias).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"
#include "lib/catmull_rom.glsl"

// This frame's sample; a: its CoC.
layout(set = 1, binding = 1, rgba16f) uniform readonly image2D rasterColor;
layout(set = 1, binding = 2, rgba16f) uniform readonly image2D history;  // anti-aliased so far
layout(set = 1, binding = 3, rg16f) uniform readonly image2D motion;  // pixels to where it was
layout(set = 1, binding = 4) uniform writeonly image2D outColor;  // rgba16f
layout(set = 1, binding = 5, rgba32f) uniform readonly image2D normalDepth;  // w linear depth
// a: what this frame's sample counts for in the average (gbuffer_resolve.comp).
layout(set = 1, binding = 6, rgba16f) uniform readonly image2D specular;
// The samples averaged into each pixel so far.
layout(set = 1, binding = 7, r16f) uniform image2D samplesAveraged;

// Whether this pipeline serves only a still view's later samples (the running average: the frame
// uniforms' rasterSample above 0; gbuffer_pass.cpp picks), made without the reprojection that a
// device running every branch under a mask would otherwise pay for on every such frame.
layout(constant_id = 0) const bool kStillSamples = false;
// Whether it serves only the first frame after a cut (no history, one sample per pixel): the
// spatial anti-aliasing below instead.
layout(constant_id = 1) const bool kFirstSample = false;

layout(push_constant) uniform Push {
  uint historyValid;  // 0 on a cut, a new viewport or the first frame
} push;

// The weight of this frame's sample in motion: the history's is the rest.
const float kMovingBlend = 0.2;

// The history at a sub-pixel position (lib/catmull_rom.glsl; edges clamped).
vec3 historyAt(vec2 position) {
  CatmullRomTaps taps = catmullRomTaps(position);
  ivec2 last = ivec2(frame.imageSize) - 1;
  vec4 sum = vec4(0.0);
  [[unroll]] for (int j = 0; j < 4; ++j) {
    [[unroll]] for (int i = 0; i < 4; ++i) {
      if (!catmullRomTapRead(i, j)) continue;
      vec3 c = imageLoad(history, clamp(taps.first + ivec2(i, j), ivec2(0), last)).rgb;
      sum += vec4(c, 1.0) * (taps.x[i] * taps.y[j]);
    }
  }
  return sum.rgb / sum.w;
}

// The first frame after a cut has one sample per pixel: the edges of its geometry are smoothed
// from the pixel's neighbourhood alone, as FXAA does (Lottes 2009). An edge pixel is blended with
// its neighbour across the edge: by how far along a stair step of the edge it lies (the step's
// ends found by walking along the edge up to kEdgeSearch pixels each way), or, for a detail smaller
// than a pixel, by how much it stands out of its neighbourhood. Only where the G-buffer's depth or
// normals step within the 3x3 neighbourhood (a silhouette, a crease, a thin line): textures are
// filtered already, and the post-process's own small blurs would soften them twice. Luma on a
// compressed scale (c / (1 + luminance)), so that a bright highlight does not hide the edges beside
// it; a light brighter than kBrightest is left as it is, since any share of it would spread its
// glare into the neighbour (a blend on the compressed scale would lose its energy instead).
const int kEdgeSearch = 8;
const float kEdgeContrastMin = 0.03;  // local luma range below which nothing is smoothed
const float kEdgeContrastRelative = 0.125;  // ... and below this share of the brightest luma
const float kSubPixelAmount = 0.75;
const float kDepthStep = 0.05;  // relative depth change between neighbours that makes an edge
const float kNormalStep = 0.9;  // ... and the cosine between their normals
const float kBrightest = 4.0;  // luminance

float compressedLuma(vec3 color) {
  float l = luminance(color);
  return l / (1.0 + l);
}

bool geometryStepsAround(ivec2 pixel) {
  ivec2 last = ivec2(frame.imageSize) - 1;
  vec4 own = imageLoad(normalDepth, pixel);
  bool steps = false;
  [[unroll]] for (int dy = -1; dy <= 1; ++dy) {
    [[unroll]] for (int dx = -1; dx <= 1; ++dx) {
      vec4 other = imageLoad(normalDepth, clamp(pixel + ivec2(dx, dy), ivec2(0), last));
      steps = steps || abs(other.w - own.w) > kDepthStep * min(other.w, own.w) ||
              dot(other.xyz, own.xyz) < kNormalStep;
    }
  }
  return steps;
}

// This frame's sample at a pixel (edges clamped), and its luma.
vec3 rasterAt(ivec2 pixel) {
  return imageLoad(rasterColor, clamp(pixel, ivec2(0), ivec2(frame.imageSize) - 1)).rgb;
}
float lumaAt(ivec2 pixel) { return compressedLuma(rasterAt(pixel)); }

// The blend of an edge pixel with its neighbour across the edge (see above), from its luma and
// its four neighbours'.
vec3 smoothEdge(ivec2 pixel, vec3 current, float lC, vec4 lNSWE, float range) {
  float lN = lNSWE.x, lS = lNSWE.y, lW = lNSWE.z, lE = lNSWE.w;
  float lNW = lumaAt(pixel + ivec2(-1, -1)), lNE = lumaAt(pixel + ivec2(1, -1));
  float lSW = lumaAt(pixel + ivec2(-1, 1)), lSE = lumaAt(pixel + ivec2(1, 1));
  // A horizontal edge (its luma changing from row to row) or a vertical one.
  float changeAcrossRows = abs(lNW - 2.0 * lW + lSW) + 2.0 * abs(lN - 2.0 * lC + lS) +
                           abs(lNE - 2.0 * lE + lSE);
  float changeAcrossColumns = abs(lNW - 2.0 * lN + lNE) + 2.0 * abs(lW - 2.0 * lC + lE) +
                              abs(lSW - 2.0 * lS + lSE);
  bool horizontal = changeAcrossRows >= changeAcrossColumns;
  float before = horizontal ? lN : lW, after = horizontal ? lS : lE;
  // The edge lies towards the neighbour with the steeper step.
  bool towardsBefore = abs(before - lC) >= abs(after - lC);
  ivec2 across = (horizontal ? ivec2(0, 1) : ivec2(1, 0)) * (towardsBefore ? -1 : 1);
  ivec2 along = horizontal ? ivec2(1, 0) : ivec2(0, 1);
  float edgeLuma = 0.5 * (lC + (towardsBefore ? before : after));
  float threshold = 0.25 * max(abs(before - lC), abs(after - lC));
  // Walk along the edge (the average of its two rows) until it departs from the edge's luma.
  int backward = kEdgeSearch, forward = kEdgeSearch;
  float backwardLuma = edgeLuma, forwardLuma = edgeLuma;
  bool searching = true;
  for (int i = 1; i <= kEdgeSearch && searching; ++i) {
    if (backward == kEdgeSearch) {
      ivec2 p = pixel - along * i;
      float l = 0.5 * (lumaAt(p) + lumaAt(p + across));
      if (abs(l - edgeLuma) >= threshold) {
        backward = i;
        backwardLuma = l;
      }
    }
    if (forward == kEdgeSearch) {
      ivec2 p = pixel + along * i;
      float l = 0.5 * (lumaAt(p) + lumaAt(p + across));
      if (abs(l - edgeLuma) >= threshold) {
        forward = i;
        forwardLuma = l;
      }
    }
    searching = backward == kEdgeSearch || forward == kEdgeSearch;
  }
  // The nearer end of the step: where the edge crosses over to this pixel's side, the pixel lies
  // under the edge's slope, by its distance from that end.
  bool backwardNearer = backward < forward;
  float endLuma = backwardNearer ? backwardLuma : forwardLuma;
  float nearest = float(min(backward, forward));
  bool crosses = (endLuma - edgeLuma < 0.0) != (lC - edgeLuma < 0.0);
  float edgeBlend = crosses ? 0.5 - nearest / float(backward + forward) : 0.0;
  // A detail smaller than a pixel: how far the pixel stands out of its neighbours' average.
  float average = (2.0 * (lN + lS + lW + lE) + lNW + lNE + lSW + lSE) / 12.0;
  float standsOut = clamp(abs(average - lC) / range, 0.0, 1.0);
  standsOut = standsOut * standsOut * (3.0 - 2.0 * standsOut);
  float subPixelBlend = standsOut * standsOut * kSubPixelAmount;
  vec3 neighbour = rasterAt(pixel + across);
  if (max(luminance(current), luminance(neighbour)) > kBrightest) return current;
  return mix(current, neighbour, max(edgeBlend, subPixelBlend));
}

vec3 spatialAntialias(ivec2 pixel, vec3 current) {
  float lC = compressedLuma(current);
  vec4 lNSWE = vec4(lumaAt(pixel + ivec2(0, -1)), lumaAt(pixel + ivec2(0, 1)),
                    lumaAt(pixel + ivec2(-1, 0)), lumaAt(pixel + ivec2(1, 0)));
  float lMax = max(lC, max(max(lNSWE.x, lNSWE.y), max(lNSWE.z, lNSWE.w)));
  float lMin = min(lC, min(min(lNSWE.x, lNSWE.y), min(lNSWE.z, lNSWE.w)));
  float range = lMax - lMin;
  vec3 result = current;
  // Loops rather than ifs: lavapipe runs an if's body whatever its lanes' conditions, but skips a
  // loop that no lane enters, and most pixels are no edge.
  for (bool contrast = range >= max(kEdgeContrastMin, kEdgeContrastRelative * lMax); contrast;
       contrast = false) {
    for (bool edge = geometryStepsAround(pixel); edge; edge = false)
      result = smoothEdge(pixel, current, lC, lNSWE, range);
  }
  return result;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(uvec2(pixel), frame.imageSize))) return;
  vec4 currentSample = imageLoad(rasterColor, pixel);
  vec3 current = currentSample.rgb;
  float currentCoc = currentSample.a;
  vec3 result = current;
  if (kFirstSample) {
    result = spatialAntialias(pixel, current);
  } else if (frame.rasterSample > 0u) {
    // This frame's samples join the average of the earlier ones.
    vec3 previous = imageLoad(history, pixel).rgb;
    float before = imageLoad(samplesAveraged, pixel).r;
    float added = imageLoad(specular, pixel).a;
    result = previous + (current - previous) * (added / (before + added));
    imageStore(samplesAveraged, pixel, vec4(before + added));
  } else if (!kStillSamples && push.historyValid != 0u) {
    // The history follows the nearest surface around the pixel (the smallest CoC is the
    // nearest): an edge moves with the silhouette that makes it, where the background's own
    // motion left a trail of the silhouette's colour, which the range (the silhouette's own
    // pixels among it) did not clamp. The range leaves out a neighbour under a wide near blur in
    // front of the pixel, and the history does not follow it: that surface's trail lived on as a
    // band of its colour beside its silhouette, an outline inside its blur, which the blur
    // spreads over the pixel anyway.
    ivec2 last = ivec2(frame.imageSize) - 1;
    vec3 low = current, high = current;
    ivec2 nearest = pixel;
    float nearestCoc = currentCoc;
    [[unroll]] for (int dy = -1; dy <= 1; ++dy) {
      [[unroll]] for (int dx = -1; dx <= 1; ++dx) {
        ivec2 q = clamp(pixel + ivec2(dx, dy), ivec2(0), last);
        vec4 other = imageLoad(rasterColor, q);
        bool bound = !wideNearBlurInFront(other.a, currentCoc);
        low = bound ? min(low, other.rgb) : low;
        high = bound ? max(high, other.rgb) : high;
        bool nearer = bound && other.a < nearestCoc;
        nearest = nearer ? q : nearest;
        nearestCoc = nearer ? other.a : nearestCoc;
      }
    }
    vec2 from = vec2(pixel) + 0.5 + imageLoad(motion, nearest).xy;
    if (all(greaterThanEqual(from, vec2(0.0))) && all(lessThan(from, vec2(frame.imageSize))))
      result = mix(clamp(historyAt(from), low, high), current, kMovingBlend);
  }
  if (frame.rasterSample == 0u) imageStore(samplesAveraged, pixel, vec4(1.0));
  imageStore(outColor, pixel, vec4(nearestHalf(result), 1.0));
}
