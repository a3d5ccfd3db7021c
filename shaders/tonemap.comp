// Output (stage 8): HDR radiance to 8-bit sRGB. The source's alpha is a sample count when it is not
// 1 (progressive accumulation), so the colour is divided by it.
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"

layout(set = 1, binding = 1) uniform sampler2D radiance;  // any float format
layout(set = 1, binding = 2, rgba8) uniform writeonly image2D display;

// Filmic curve fitted to ACES (Narkowicz 2015).
vec3 filmic(vec3 x) {
  return clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// The sRGB curve; its power 1 / 2.4 as a sum of square roots (within a quarter of an 8-bit step
// of the exact curve): a power is a logarithm and an exponential per channel, slower on a CPU
// device.
vec3 srgbEncode(vec3 linear) {
  vec3 root2 = sqrt(linear), root4 = sqrt(root2), root8 = sqrt(root4);
  vec3 curve =
      0.662002687 * root2 + 0.684122060 * root4 - 0.323583601 * root8 - 0.022541147 * linear;
  return mix(linear * 12.92, curve, greaterThan(linear, vec3(0.0031308)));
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(uvec2(pixel), frame.imageSize))) return;
  vec4 value = texelFetch(radiance, pixel, 0);
  vec3 color = value.a > 0.0 ? value.rgb / value.a : vec3(0.0);
  imageStore(display, pixel, vec4(srgbEncode(filmic(color * frame.exposure)), 1.0));
}
