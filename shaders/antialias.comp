// G-buffer (stage 1), anti-aliasing step: the raster's colour accumulated over frames. While the
// view rests every frame adds a sample at another sub-pixel position (a Halton sequence), and the
// running average converges to a supersampled image (a box filter over the pixel, as the ray
// tracers' jittered rays) of kMaxRasterSamples samples, after which the step no longer runs. When
// the view moves, each frame samples another jittered position and the history is reprojected by
// the motion vectors, clamped to the range of this frame's 3x3 neighbourhood (no ghosting where the
// surface changed) and blended in, so that edges stay smooth in motion where the picture allows it.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"

layout(set = 1, binding = 1, rgba16f) uniform readonly image2D rasterColor;  // this frame's sample
layout(set = 1, binding = 2, rgba16f) uniform readonly image2D history;  // anti-aliased so far
layout(set = 1, binding = 3, rg16f) uniform readonly image2D motion;  // pixels to where it was
layout(set = 1, binding = 4) uniform writeonly image2D outColor;  // rgba16f

// Whether this pipeline serves only a still view's later samples (the running average: the frame
// uniforms' rasterSample above 0; gbuffer_pass.cpp picks), made without the reprojection that a
// device running every branch under a mask would otherwise pay for on every such frame.
layout(constant_id = 0) const bool kStillSamples = false;

layout(push_constant) uniform Push {
  uint historyValid;  // 0 on a cut, a new viewport or the first frame
} push;

// The weight of this frame's sample in motion: the history's is the rest.
const float kMovingBlend = 0.2;

// The history at a sub-pixel position, bilinear over texel centres (edges clamped).
vec3 historyAt(vec2 position) {
  vec2 p = position - 0.5;
  ivec2 base = ivec2(floor(p));
  vec2 f = p - vec2(base);
  ivec2 last = ivec2(frame.imageSize) - 1;
  vec3 c00 = imageLoad(history, clamp(base, ivec2(0), last)).rgb;
  vec3 c10 = imageLoad(history, clamp(base + ivec2(1, 0), ivec2(0), last)).rgb;
  vec3 c01 = imageLoad(history, clamp(base + ivec2(0, 1), ivec2(0), last)).rgb;
  vec3 c11 = imageLoad(history, clamp(base + ivec2(1, 1), ivec2(0), last)).rgb;
  return mix(mix(c00, c10, f.x), mix(c01, c11, f.x), f.y);
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(uvec2(pixel), frame.imageSize))) return;
  vec3 current = imageLoad(rasterColor, pixel).rgb;
  vec3 result = current;
  if (frame.rasterSample > 0u) {
    vec3 previous = imageLoad(history, pixel).rgb;
    float samples = float(frame.rasterSample + 1u);
    result = previous + (current - previous) / samples;
  } else if (!kStillSamples && push.historyValid != 0u) {
    vec2 from = vec2(pixel) + 0.5 + imageLoad(motion, pixel).xy;
    if (all(greaterThanEqual(from, vec2(0.0))) && all(lessThan(from, vec2(frame.imageSize)))) {
      vec3 low = current, high = current;
      ivec2 last = ivec2(frame.imageSize) - 1;
      [[unroll]] for (int dy = -1; dy <= 1; ++dy) {
        [[unroll]] for (int dx = -1; dx <= 1; ++dx) {
          vec3 c = imageLoad(rasterColor, clamp(pixel + ivec2(dx, dy), ivec2(0), last)).rgb;
          low = min(low, c);
          high = max(high, c);
        }
      }
      result = mix(clamp(historyAt(from), low, high), current, kMovingBlend);
    }
  }
  imageStore(outColor, pixel, vec4(result, 1.0));
}
