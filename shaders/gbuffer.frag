// G-buffer: shaded sharp colour (the shared shading function), its specular part, normal and
// linear view depth.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/scene.glsl"
#include "lib/frame.glsl"
#include "lib/shading.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
layout(location = 3) in float inUvPerMeter;
layout(location = 4) flat in uint inMaterial;

layout(location = 0) out vec4 outColor;
layout(location = 1) out vec4 outSpecular;
layout(location = 2) out vec4 outNormalDepth;

void main() {
  SurfacePoint s;
  s.position = inPosition;
  s.normal = inNormal;
  s.uv = inUv;
  s.uvPerMeter = inUvPerMeter;
  s.material = inMaterial;
  vec3 toEye = frame.eye.xyz - inPosition;
  float distance = length(toEye);
  vec3 specular;
  vec3 color = shadeSurface(s, toEye / distance, distance * pixelAngle(), specular);
  outColor = vec4(color, 1.0);
  outSpecular = vec4(specular, 1.0);
  float linearDepth = dot(inPosition - frame.eye.xyz, frame.forward.xyz);
  outNormalDepth = vec4(normalize(inNormal), linearDepth);
}
