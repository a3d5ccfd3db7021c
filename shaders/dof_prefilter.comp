// Post-process DoF (stage 2), prefilter: a 9-tap disc of about the gather's ring spacing around
// each half-resolution pixel, so that the sparse gather taps cannot miss a small bright highlight:
// its energy spreads over the gap between taps and its bokeh comes out a filled disc, not dots.
// Only similar CoCs mix, and no pixel gathers from further away than its own CoC.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"

layout(set = 1, binding = 1, rgba16f) uniform readonly image2D halfColorCoc;
layout(set = 1, binding = 2, rg16f) uniform readonly image2D dilatedTiles;
layout(set = 1, binding = 3, rgba16f) uniform writeonly image2D prefiltered;

// Covering a lattice of taps spacing s apart needs a radius of about s / sqrt(2).
const float kGapFill = 0.7;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = halfImageSize();
  if (any(greaterThanEqual(pixel, size))) return;
  vec4 center = imageLoad(halfColorCoc, pixel);
  float tileCoc = imageLoad(dilatedTiles, tileOfHalfResPixel(pixel)).x;
  float radius = min(kGapFill * ringSpacing(tileCoc), abs(center.a) * 0.25);
  // Below one pixel there are no gaps between taps to fill, and filtering would only blur.
  if (tileCoc < kDofFocusZone || radius < 1.0) {
    imageStore(prefiltered, pixel, center);
    return;
  }
  vec4 sum = vec4(center.rgb, 1.0);
  [[unroll]] for (int i = 0; i < 8; ++i) {
    float angle = float(i) * (kPi / 4.0);
    ivec2 source = clamp(ivec2(floor(vec2(pixel) + 0.5 + radius * vec2(cos(angle), sin(angle)))),
                         ivec2(0), size - 1);
    vec4 tap = imageLoad(halfColorCoc, source);
    sum += vec4(tap.rgb, 1.0) * cocSimilarity(tap.a, center.a);
  }
  imageStore(prefiltered, pixel, vec4(sum.rgb / sum.w, center.a));
}
