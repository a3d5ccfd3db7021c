// Debug views of the hybrid (stage 7, drawn in place of the composite and timed as
// hybrid_composite), as HDR colour for the tonemap: the ray mask (rays per pixel over the cap), the
// accumulated hit ratio, the signed circle of confusion (near field blue, far field red, the focus
// zone black), and the near and far layers as the spatial reconstruction (stage 6) left them.
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "shared/debug_view.h"
#include "shared/dof.h"

layout(set = 1, binding = 1) uniform usampler2D rays;  // r8ui
layout(set = 1, binding = 2) uniform sampler2D normalDepth;  // rgba32f
layout(set = 1, binding = 3) uniform sampler2D historyNear;  // rgba16f: colour x ratio, ratio
layout(set = 1, binding = 4) uniform sampler2D historyFar;  // rgba16f: colour x (1 - ratio)
layout(set = 1, binding = 5) uniform writeonly image2D outColor;  // rgba16f

layout(push_constant) uniform Push {
  uint view;  // kDebugView* (shared/debug_view.h)
} push;

// The tonemap's filmic curve maps this to about white.
const float kWhite = 8.0;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(uvec2(pixel), frame.imageSize))) return;
  bool traced = texelFetch(rays, pixel, 0).r > 0u;
  vec3 color = vec3(0.0);
  if (push.view == kDebugViewMask) {
    color = vec3(float(texelFetch(rays, pixel, 0).r) / float(max(frame.samplesPerPixel, 1u))) * kWhite;
  } else if (push.view == kDebugViewHitRatio) {
    color = traced ? vec3(texelFetch(historyNear, pixel, 0).a) * kWhite : vec3(0.0, 0.0, 0.05);
  } else if (push.view == kDebugViewCoc) {
    float depth = texelFetch(normalDepth, pixel, 0).w;
    float coc = pixelCoc(depth);
    float level = abs(coc) < kDofFocusZone ? 0.0 : min(abs(coc) / 32.0, 1.0) * kWhite;
    color = coc < 0.0 ? vec3(0.1, 0.3, 1.0) * level : vec3(1.0, 0.3, 0.1) * level;
  } else if (push.view == kDebugViewNear) {
    vec4 near = texelFetch(historyNear, pixel, 0);
    color = traced && near.a > 0.0 ? near.rgb / near.a : vec3(0.0);
  } else if (push.view == kDebugViewFar) {
    float farShare = 1.0 - texelFetch(historyNear, pixel, 0).a;
    color = traced && farShare > 0.0 ? texelFetch(historyFar, pixel, 0).rgb / farShare : vec3(0.0);
  }
  imageStore(outColor, pixel, vec4(color, 1.0));
}
