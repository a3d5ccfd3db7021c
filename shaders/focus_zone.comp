// The in-focus zone over the finished hybrid image (the focus_zone debug view, after the
// composite): pixels whose sensor circle of confusion is within the acceptable circle are tinted
// green, so the zone between the near and far limits of acceptable sharpness that the client
// shows (render/lens_optics.h) can be seen in the picture. It uses the same sensor formula as
// those limits, not the pixel CoC of the blur, so the two agree exactly.
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"

layout(set = 1, binding = 1) uniform sampler2D normalDepth;  // rgba32f
layout(set = 1, binding = 2, rgba16f) uniform image2D color;  // the composite, tinted in place

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(uvec2(pixel), frame.imageSize))) return;
  float depth = texelFetch(normalDepth, pixel, 0).w;
  if (cocOnSensor(depth, frame.focalLength, frame.fNumber, frame.focusDistance) > frame.acceptableCoc)
    return;
  vec4 c = imageLoad(color, pixel);
  // Darken red and blue and lift green: the picture stays readable under the tint.
  imageStore(color, pixel, vec4(c.rgb * vec3(0.45, 0.9, 0.45) + vec3(0.0, 0.35, 0.05), c.a));
}
