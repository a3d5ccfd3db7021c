// Hybrid composite (stage 7): where the ray mask traced, the ray-traced layers as the spatial
// reconstruction (stage 6) left them, joined by the accumulated hit ratio and placed by the pixel's
// circle of confusion: in the focus zone the sharp raster colour seen past the near layer, handed
// over to the traced colour as rays add up (on a still view as their count weighs against the
// raster's samples); in the near field the ray-traced colour, except bright specular bokeh where
// the post-process wins by the specular intensity; in the far field the ray-traced colour where
// near geometry covers the pixel (hit ratio) and inside the traced region (while the camera moves,
// half of it), fading to the post-process over the last pixels before the mask's edge, so that the
// edge leaves no seam. In the near field and inside the traced region, the traced colour is shown
// as far as it differs from the post-process by more than its noise. One thread per pixel of the
// ray mask's work list: the others hold the post-process's colour already (step
// hybrid_composite_copy).
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"
#include "shared/ray_work.h"
#include "lib/skippable.glsl"

HDOF_RAY_WORK_LIST(9, readonly);
layout(set = 1, binding = 1, r8ui) uniform readonly uimage2D rays;
layout(set = 1, binding = 2, rgba16f) uniform readonly image2D sharp;  // the G-buffer's colour
layout(set = 1, binding = 3, rgba16f) uniform readonly image2D specular;  // its specular part
layout(set = 1, binding = 4, rgba32f) uniform readonly image2D normalDepth;
layout(set = 1, binding = 5, rgba16f) uniform readonly image2D postProcess;
// Near: colour x ratio, ratio; far: colour x (1 - ratio), rays.
layout(set = 1, binding = 6, rgba16f) uniform readonly image2D historyNear;
layout(set = 1, binding = 7, rgba16f) uniform readonly image2D historyFar;
layout(set = 1, binding = 8) uniform writeonly image2D outColor;  // rgba16f
// Per tile, whether a near-field blur wider than the tile dilation reaches it (ray_mask_far.comp).
layout(set = 1, binding = 10, r16f) uniform readonly image2D farTiles;
layout(set = 1, binding = 11, r16f) uniform readonly image2D samplesAveraged;  // in `sharp`
// rg16f: each traced pixel's difference from the post-process and noise (hybrid_spatial.comp).
layout(set = 1, binding = 12, rg16f) uniform readonly image2D difference;

// Whether this pipeline serves frames in which the camera moved (hybrid_dof.cpp picks): a
// constant rather than the frame uniforms' two matrices compared in every thread, which cost the
// pass about 2 ms of a moving frame single-threaded on lavapipe.
layout(constant_id = 0) const bool kCameraMoved = false;

// Hit ratio over which the far field turns from post-process to ray-traced colour.
const float kFarBlendRatio = 0.1;
// Distance from the mask's edge (pixels) over which the far field fades to the post-process.
const float kSeamFade = 1.0;
// Rays accumulated at which the focus zone shows the traced colour rather than the raster's.
const float kConvergedRays = 32.0;
// On a still view, an in-focus pixel's rays and the raster's jittered samples estimate the same
// antialiased pixel: the traced colour's share is at least its rays' share of all samples, a
// raster sample counting as this many rays (the raster lacks the lens's blur under a pixel).
const float kRasterSampleRays = 2.0;
// Specular radiance at which a near-field bokeh highlight is left to the post-process.
const float kBokehSpecular = 4.0;
// The share of the far field's traced colour inside the traced region while the camera moves.
const float kMovingInside = 0.5;

// How far inside the traced region the pixel lies: the share of eight pixels on a circle of
// radius kSeamFade around it that the mask traced, from 0.5 on the edge to 1 well inside.
float tracedShare(ivec2 pixel) {
  float count = 0.0;
  for (int i = 0; i < 8; ++i) {
    float angle = float(i) * (kPi / 4.0);
    ivec2 q = pixel + ivec2(round(kSeamFade * vec2(cos(angle), sin(angle))));
    q = clamp(q, ivec2(0), ivec2(frame.imageSize) - 1);
    count += imageLoad(rays, q).r > 0u ? 1.0 : 0.0;
  }
  return count / 8.0;
}

// How far the pixel lies inside the tiles that such a blur reaches: the tiles' marks interpolated
// between their centres, so that the traced colour fades in over a tile's width. A tile's own mark
// switched the traced colour on and off at its border: where the blur's true reach is wider than
// the marked tiles, their rectangles stood out of the post-process around them.
float farTilesAt(ivec2 pixel) {
  vec2 position = (vec2(pixel) + 0.5) / float(kDofTileSize) - 0.5;
  ivec2 first = ivec2(floor(position));
  vec2 f = position - vec2(first);
  ivec2 last = tileCount() - 1;
  float sum = 0.0;
  for (int i = 0; i < 4; ++i) {
    ivec2 corner = ivec2(i & 1, i >> 1);
    vec2 weights = mix(1.0 - f, f, vec2(corner));
    float marked = imageLoad(farTiles, clamp(first + corner, ivec2(0), last)).x > 0.0 ? 1.0 : 0.0;
    sum += weights.x * weights.y * marked;
  }
  return sum;
}

// How much of the traced colour a pixel shows, once its rays are trusted: the share of the traced
// colour's squared difference from the post-process that is the post-process's error rather than
// the traced colour's noise, both summed over the 3x3 pixels (a positive-part James-Stein weight).
// Where the post-process renders the blur well (a far blur of similar depths) the difference is
// noise, and the post-process's smooth colour stays until the rays' noise falls below its error;
// where it is wrong (partial occlusion, a halo, a disc it misses) the difference stands out of the
// noise. Neighbours whose noise is not measured (0: not traced, or a short history) do not count.
float tracedBeyondNoise(ivec2 pixel) {
  float squared = 0.0, noise = 0.0;
  ivec2 last = ivec2(frame.imageSize) - 1;
  for (int i = 0; i < 9; ++i) {
    vec2 q = imageLoad(difference, clamp(pixel + ivec2(i % 3 - 1, i / 3 - 1), ivec2(0), last)).xy;
    if (q.y == 0.0) continue;
    squared += q.x * q.x;
    noise += q.y * q.y;
  }
  return squared > noise ? 1.0 - noise / squared : 0.0;
}

void main() {
  if (gl_GlobalInvocationID.x >= workList.header.count) return;
  ivec2 pixel = ivec2(unpackRayWorkPixel(workList.entries[gl_GlobalInvocationID.x].x));
  vec3 pp = imageLoad(postProcess, pixel).rgb;
  vec4 near = imageLoad(historyNear, pixel);
  float ratio = clamp(near.a, 0.0, 1.0);
  vec4 far = imageLoad(historyFar, pixel);
  vec3 traced = near.rgb + far.rgb;
  float depth = imageLoad(normalDepth, pixel).w;
  float coc = pixelCoc(depth);
  // A pixel whose history is short (the first frames of a view, or in motion) is noisy: the
  // post-process shares it, in every zone, up to kHybridTrustedRays (48) rays; while the camera
  // moves, up to kHybridMovingTrustedRays (24). A pixel that the mask gives fewer rays (a blur
  // wide on both sides of its edge) is still noisier than the post-process after 32 of its own:
  // handed over by then, it made a resting view worse for a while.
  // Where a near-field blur wider than the post-process renders (kDofMaxCoc) reaches, the
  // post-process shows a near object too narrow and too solid, wrong by far more than a few rays'
  // noise: the traced colour from the first ray, fading in across the marked tiles' border.
  float beyondPostProcess = farTilesAt(pixel);
  float trustedRays = kCameraMoved ? kHybridMovingTrustedRays : kHybridTrustedRays;
  float trust = mix(clamp(far.a / trustedRays, 0.0, 1.0), 1.0, beyondPostProcess);
  // Out of the focus zone, where the pixel's own noise is measured.
  float beyondNoise = 1.0;
  SKIPPABLE_IF(abs(coc) >= kDofFocusZone && imageLoad(difference, pixel).y > 0.0) {
    beyondNoise = tracedBeyondNoise(pixel);
  }
  vec3 color;
  if (abs(coc) < kDofFocusZone) {
    // Past the near layer, the in-focus surface is the sharp raster's, until the rays traced
    // there are enough to give it the antialiased edges of the traced image; on a still view,
    // from the first frames as far as they outnumber the raster's samples.
    vec3 raster = imageLoad(sharp, pixel).rgb * (1.0 - ratio) + near.rgb;
    float converged = clamp(far.a / kConvergedRays, 0.0, 1.0);
    color = mix(pp, mix(raster, traced, converged), trust);
    if (viewRests()) {
      float samples = imageLoad(samplesAveraged, pixel).r;
      float counted = far.a / (far.a + kRasterSampleRays * samples);
      float shown = converged * trust;
      color = mix(color, traced, max(counted - shown, 0.0) / max(1.0 - shown, 1e-3));
    }
  } else if (coc < 0.0) {
    float bokeh = clamp(luminance(imageLoad(specular, pixel).rgb) / kBokehSpecular, 0.0, 1.0);
    color = mix(pp, traced, trust * (1.0 - bokeh) * beyondNoise);
  } else {
    // Where no near geometry covers the pixel the traced colour refines a far blur that the
    // post-process renders too. While the camera moves its noise is not measured (the history's
    // window is a few frames), so there it shows at half the weight.
    float inside = smoothstep(0.5, 1.0, tracedShare(pixel)) * (kCameraMoved ? kMovingInside : 1.0);
    color = mix(pp, traced,
                trust * max(smoothstep(0.0, kFarBlendRatio, ratio), inside * beyondNoise));
  }
  imageStore(outColor, pixel, vec4(color, 1.0));
}
