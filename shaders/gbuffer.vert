// G-buffer (stage 1), visibility step: every triangle's three corners in a row (a non-indexed
// draw), so the triangle's number is the vertex number / 3 on all three corners: no primitive-id
// support needed, and the same value whichever corner is the provoking one.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/frame.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 0) flat out uint outTriangle;

void main() {
  outTriangle = uint(gl_VertexIndex) / 3u;
  gl_Position = frame.viewProj * vec4(inPosition, 1.0);
  // This frame's anti-aliasing sample position within the pixel: the geometry moves the other
  // way, so that the pixel centre covers what lies at centre + jitter (clip space scales with w).
  gl_Position.xy -= frame.rasterJitter * (2.0 / vec2(frame.imageSize)) * gl_Position.w;
}
