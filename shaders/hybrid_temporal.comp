// Temporal accumulation of the hybrid's ray-traced layers (stage 5; an exponential moving average,
// as in TAA): the near layer reprojected with the motion vectors, the far layer through its average
// far world position (the neighbours' where a pixel had no far hit), both read between texels
// where the camera moved (Catmull-Rom), history rejected where the surface under the near
// reprojection changed depth (disocclusion) or on a cut, and, while the camera moves or the lens
// changes, clamped to the range of this frame's rays around the pixel, with a shorter window
// (everywhere: a blurred near silhouette moves with its own parallax, not with the surface behind
// it, so a slowly moving background pixel holds stale near colour too; a focus pull moves every
// blur); luminance moments give the variance that the next frame's ray mask (stage 3) reads, newly
// traced pixels counting as noisy. One thread per pixel of the ray mask's work list; the others'
// history was cleared (step hybrid_history_clear: pixels the mask left out this frame drop their
// history), or, on a resting view whose pixels take their rays in turns, stands (accumulated in
// place).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 64) in;

#include "lib/frame.glsl"
#include "shared/ray_work.h"
#include "lib/catmull_rom.glsl"

layout(set = 1, binding = 1, r8ui) uniform readonly uimage2D rays;  // rays traced this frame
layout(set = 1, binding = 2, rgba16f) uniform readonly image2D nearLayer;  // colour, hit ratio
layout(set = 1, binding = 3, rgba16f) uniform readonly image2D farLayer;  // colour, 1 - hit ratio
layout(set = 1, binding = 4, rgba32f) uniform readonly image2D farPosition;  // xyz, w far weight
layout(set = 1, binding = 5, rg16f) uniform readonly image2D motion;  // pixels
layout(set = 1, binding = 6, rgba32f) uniform readonly image2D normalDepth;  // w linear depth
// History: the layers' colours premultiplied by their share of the rays (near by the hit ratio,
// far by one minus it), so that frames in which a layer got no rays count as its absence, not
// as black, and near + far is the pixel's colour; the near alpha is the accumulated hit ratio.
// Near: colour x ratio, ratio; far: colour x (1 - ratio), rays; moments: m1, m2, rays, depth.
layout(set = 1, binding = 7, rgba32f) uniform readonly image2D historyNear;
layout(set = 1, binding = 8, rgba32f) uniform readonly image2D historyFar;
layout(set = 1, binding = 9, rgba32f) uniform readonly image2D historyMoments;
HDOF_RAY_WORK_LIST(10, readonly);
layout(set = 1, binding = 11) uniform writeonly image2D outNear;
layout(set = 1, binding = 12) uniform writeonly image2D outFar;
layout(set = 1, binding = 13) uniform writeonly image2D outMoments;
// rg16f: the variance of one ray's luminance (the frame's variance times its rays, so that it
// does not change with the rays the mask gives the pixel), and the rays accumulated.
layout(set = 1, binding = 14) uniform writeonly image2D outVariance;

// Which frames this pipeline serves (hybrid_dof.cpp picks by the frame uniforms; a device that
// runs every branch under a mask pays for the loads of one not taken): kChangedFrames, those in
// which the camera or the lens changed (history clamped to this frame's rays, 27 loads), else
// only the others; kMovedFrames, those in which the camera moved (history reprojected, 11 loads),
// else only the others: in a lens change (a focus pull) nothing moved on screen either.
layout(constant_id = 0) const bool kChangedFrames = true;
layout(constant_id = 1) const bool kMovedFrames = true;

layout(push_constant) uniform Push {
  uint reset;  // 1 on a camera cut or the first frame: no history at all
  float minBlend;  // the moving average's weight of the new frame once history is long
} push;

const float kDisocclusion = 0.1;  // relative depth change that rejects the near history
// The moving average's floor while the camera moves: a shorter window, that lags less.
const float kMovingMinBlend = 0.4;
// ... and while the lens changes (a focus pull): four frames, so that the blur keeps up with the
// focus (ten frames trailed it by a visible step) without the noise of motion's window.
const float kLensMinBlend = 0.25;

bool insideImage(vec2 p) { return all(greaterThanEqual(p, vec2(0.0))) && all(lessThan(p, vec2(frame.imageSize))); }

// The far world position this pixel sees through the near layer: its own, else the weighted
// average of its 3x3 neighbours' (valid when w > 0).
vec4 farWorldPosition(ivec2 pixel) {
  vec4 own = imageLoad(farPosition, pixel);
  if (own.w > 0.0) return vec4(own.xyz, 1.0);
  vec4 sum = vec4(0.0);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 q = clamp(pixel + ivec2(dx, dy), ivec2(0), ivec2(frame.imageSize) - 1);
      vec4 p = imageLoad(farPosition, q);
      if (imageLoad(rays, q).r > 0u && p.w > 0.0) sum += vec4(p.xyz * p.w, p.w);
    }
  return sum.w > 0.0 ? vec4(sum.xyz / sum.w, 1.0) : vec4(0.0);
}

// The range of this frame's premultiplied layers over the traced pixels of the 3x3 neighbourhood.
struct NeighbourRange {
  vec4 nearMin, nearMax;
  vec3 farMin, farMax;
};

NeighbourRange neighbourRange(ivec2 pixel) {
  NeighbourRange range = NeighbourRange(vec4(1e30), vec4(-1e30), vec3(1e30), vec3(-1e30));
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 q = clamp(pixel + ivec2(dx, dy), ivec2(0), ivec2(frame.imageSize) - 1);
      if (imageLoad(rays, q).r == 0u) continue;
      vec4 n = imageLoad(nearLayer, q);
      vec4 nearNow = vec4(n.rgb * n.a, n.a);
      vec3 farNow = imageLoad(farLayer, q).rgb * (1.0 - n.a);
      range.nearMin = min(range.nearMin, nearNow);
      range.nearMax = max(range.nearMax, nearNow);
      range.farMin = min(range.farMin, farNow);
      range.farMax = max(range.farMax, farNow);
    }
  return range;
}

// Between texels, where the camera moved: the weights of the history's texels around a position
// in the previous frame (tap (i, j) at first + (i, j), as lib/catmull_rom.glsl numbers them),
// Catmull-Rom where each texel it reads has history, else bilinear over those of the 2x2 nearest
// that have (the nearest has: the caller checks it), normalised. A texel without history holds a
// stale colour. The nearest texel alone, as the frames without motion read it, moved the history
// by up to half a pixel at every frame of motion, and the traced colour that the composite shows
// came out misplaced at edges.
struct HistoryTaps {
  ivec2 first;
  bool complete;  // every texel read has history: Catmull-Rom
  vec4 x, y;      // its weights along x and y, x normalised over the texels read
  vec4 bilinear;  // else taps (1, 1), (2, 1), (1, 2) and (2, 2), normalised
};

ivec2 tapTexel(ivec2 first, int i, int j) {
  return clamp(first + ivec2(i, j), ivec2(0), ivec2(frame.imageSize) - 1);
}

HistoryTaps historyTaps(vec2 position) {
  CatmullRomTaps catmullRom = catmullRomTaps(position);
  vec2 f = position - 0.5 - vec2(catmullRom.first + 1);  // past the centre of tap (1, 1)
  vec4 bilinear = vec4(1.0 - f.x, f.x, 1.0 - f.x, f.x) * vec4(1.0 - f.y, 1.0 - f.y, f.y, f.y);
  bool complete = true;
  [[unroll]] for (int j = 0; j < 4; ++j) {
    [[unroll]] for (int i = 0; i < 4; ++i) {
      if (!catmullRomTapRead(i, j)) continue;
      bool has = imageLoad(historyMoments, tapTexel(catmullRom.first, i, j)).z > 0.0;
      complete = complete && has;
      if (!has && i >= 1 && i <= 2 && j >= 1 && j <= 2) bilinear[(j - 1) * 2 + (i - 1)] = 0.0;
    }
  }
  float corners = (catmullRom.x[0] + catmullRom.x[3]) * (catmullRom.y[0] + catmullRom.y[3]);
  return HistoryTaps(catmullRom.first, complete, catmullRom.x / (1.0 - corners), catmullRom.y,
                     bilinear / max(dot(bilinear, vec4(1.0)), 1e-6));
}

float tapWeight(HistoryTaps taps, int i, int j) {
  if (taps.complete) return taps.x[i] * taps.y[j];
  bool inner = i >= 1 && i <= 2 && j >= 1 && j <= 2;
  return inner ? taps.bilinear[(j - 1) * 2 + (i - 1)] : 0.0;
}

vec4 nearHistoryAt(vec2 position) {
  HistoryTaps taps = historyTaps(position);
  vec4 sum = vec4(0.0);
  [[unroll]] for (int j = 0; j < 4; ++j)
    [[unroll]] for (int i = 0; i < 4; ++i)
      if (catmullRomTapRead(i, j))
        sum += tapWeight(taps, i, j) * imageLoad(historyNear, tapTexel(taps.first, i, j));
  return sum;
}

vec3 farHistoryAt(vec2 position) {
  HistoryTaps taps = historyTaps(position);
  vec3 sum = vec3(0.0);
  [[unroll]] for (int j = 0; j < 4; ++j)
    [[unroll]] for (int i = 0; i < 4; ++i)
      if (catmullRomTapRead(i, j))
        sum += tapWeight(taps, i, j) * imageLoad(historyFar, tapTexel(taps.first, i, j)).rgb;
  return sum;
}

vec2 pixelOf(mat4 viewProj, vec3 world) {
  vec4 clip = viewProj * vec4(world, 1.0);
  return (clip.xy / clip.w * 0.5 + 0.5) * vec2(frame.imageSize);
}

// How a world point moved on screen since the previous frame (previous minus current). The far
// layer's average position seen through the lens need not project onto this pixel, but it moves
// as the background it stands for does.
vec2 screenMotion(vec3 world) {
  return pixelOf(frame.previousViewProj, world) - pixelOf(frame.viewProj, world);
}

void main() {
  if (gl_GlobalInvocationID.x >= workList.header.count) return;
  uvec2 entry = workList.entries[gl_GlobalInvocationID.x];
  ivec2 pixel = ivec2(unpackRayWorkPixel(entry.x));
  float depth = imageLoad(normalDepth, pixel).w;
  vec4 near = imageLoad(nearLayer, pixel);
  vec4 far = imageLoad(farLayer, pixel);
  vec2 center = vec2(pixel) + 0.5;

  // The pixel's statistics: where the surface under it was, if it was that surface. In a frame
  // in which the camera did not move (kMovedFrames false) nothing moved on screen: both layers'
  // history is this pixel's.
  vec2 previousPixel = kMovedFrames ? center + imageLoad(motion, pixel).xy : center;
  vec4 moments = vec4(0.0);
  bool pixelValid = push.reset == 0u && insideImage(previousPixel);
  if (pixelValid) {
    moments = imageLoad(historyMoments, ivec2(previousPixel));
    pixelValid = moments.z > 0.0 && abs(moments.w - depth) <= kDisocclusion * depth;
  }
  // The moving average counts rays, not frames (the mask gives a pixel more or fewer rays from
  // frame to frame): a frame's weight is its share of the rays in the window, which is
  // 1 / minBlend frames at the full rays per pixel.
  float rays = float(entry.y);
  // The camera moved: this pipeline serves only such frames (hybrid_dof.cpp picks it when the
  // frame's matrices differ; comparing them here cost every thread 32 loads and compares).
  bool moving = kMovedFrames;
  // A lens change (a focus pull) moves the blur as motion moves the image: the history is clamped
  // to this frame's rays as in motion, over the window that follows a change.
  bool changed = kChangedFrames && (moving || frame.stillFrames == 0u);
  float minBlend = moving ? kMovingMinBlend : changed ? max(push.minBlend, kLensMinBlend) : push.minBlend;
  float window = float(max(frame.samplesPerPixel, 1u)) / minBlend;
  float samples = pixelValid ? moments.z : 0.0;
  float accumulated = min(samples + rays, window);
  float blend = rays / accumulated;
  vec4 nearNow = vec4(near.rgb * near.a, near.a);
  vec3 farNow = far.rgb * (1.0 - near.a);
  // Near layer: with the surface under the pixel.
  vec4 nearHistory = !pixelValid  ? nearNow
                     : kMovedFrames ? nearHistoryAt(previousPixel)
                                    : imageLoad(historyNear, ivec2(previousPixel));

  // Far layer: where the background seen through this pixel was.
  bool farValid = push.reset == 0u && moments.z > 0.0;
  vec2 previousFar = previousPixel;
  if (kMovedFrames) {
    vec4 world = farWorldPosition(pixel);
    if (world.w > 0.0) previousFar = center + screenMotion(world.xyz);
    farValid = push.reset == 0u && insideImage(previousFar) &&
               imageLoad(historyMoments, ivec2(previousFar)).z > 0.0;
  }
  vec3 farHistory = !farValid    ? farNow
                    : kMovedFrames ? farHistoryAt(previousFar)
                                   : imageLoad(historyFar, ivec2(previousFar)).rgb;
  // In motion, history outside what this frame's rays around the pixel saw is stale (a layer
  // moved over or off it): clamped into their range, as TAA does.
  if (changed) {
    NeighbourRange range = neighbourRange(pixel);
    nearHistory = clamp(nearHistory, range.nearMin, range.nearMax);
    farHistory = clamp(farHistory, range.farMin, range.farMax);
  }
  vec3 outFarColor = mix(farHistory, farNow, farValid ? blend : 1.0);
  vec4 outNearValue = mix(nearHistory, nearNow, blend);

  float lum = luminance(near.rgb * near.a + far.rgb * (1.0 - near.a));
  vec2 m = pixelValid ? mix(moments.xy, vec2(lum, lum * lum), blend) : vec2(lum, lum * lum);
  // A short history (under four frames of the pixel's rays) says little about the variance: such
  // pixels ask for full rays, and the spatial pass lets them borrow freely. Counted in the
  // pixel's own frames, so that one the mask gives fewer rays (rays by CoC) is not held at that
  // stage, over-smoothed, for longer.
  float variance = accumulated < 4.0 * rays
                       ? kRayMaskVarianceNew
                       : max(m.y - m.x * m.x, 0.0) * rays;
  imageStore(outNear, pixel, outNearValue);
  imageStore(outFar, pixel, vec4(outFarColor, accumulated));
  imageStore(outMoments, pixel, vec4(m, accumulated, depth));
  imageStore(outVariance, pixel, vec4(variance, accumulated, 0.0, 0.0));
}
