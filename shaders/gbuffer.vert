// G-buffer: the whole scene is one world-space vertex/index soup drawn in one call.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/frame.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in float inUvPerMeter;
layout(location = 2) in vec3 inNormal;
layout(location = 3) in uint inMaterial;
layout(location = 4) in vec2 inUv;

layout(location = 0) out vec3 outPosition;
layout(location = 1) out vec3 outNormal;
layout(location = 2) out vec2 outUv;
layout(location = 3) out float outUvPerMeter;
layout(location = 4) flat out uint outMaterial;

void main() {
  outPosition = inPosition;
  outNormal = inNormal;
  outUv = inUv;
  outUvPerMeter = inUvPerMeter;
  outMaterial = inMaterial;
  gl_Position = frame.viewProj * vec4(inPosition, 1.0);
}
