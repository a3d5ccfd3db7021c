// Random numbers and sample patterns for the ray tracers.
#ifndef HDOF_LIB_SAMPLING_GLSL
#define HDOF_LIB_SAMPLING_GLSL
#include "shared/math.h"

uint pcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

float toUnitFloat(uint bits) { return float(bits >> 8) * (1.0 / 16777216.0); }

// A per-pixel random offset in [0,1)^2 that decorrelates the low-discrepancy sequence below.
vec2 pixelRotation(uvec2 pixel, uint salt) {
  uint h = pcgHash(pixel.x * 1973u + pixel.y * 9277u + salt * 26699u);
  return vec2(toUnitFloat(h), toUnitFloat(pcgHash(h)));
}

// Point i of the R2 sequence (Roberts 2018), rotated: well spread for every prefix length.
vec2 r2Sample(uint i, vec2 rotation) {
  return fract(rotation + float(i) * vec2(0.7548776662466927, 0.5698402909980532));
}

// Point i of the 4-D Kronecker sequence with the generalised golden ratio (Roberts 2018), rotated:
// for ray samples that choose a pixel position and a lens position together. In 0.32 fixed
// point, so that it is as exact for the millionth sample as for the first.
vec4 r4Sample(uint i, vec4 rotation) {
  const uvec4 alpha = uvec4(3679390609u, 3152041523u, 2700274805u, 2313257605u);  // x 2^32
  return fract(rotation + vec4((i * alpha) >> 8u) * (1.0 / 16777216.0));
}

vec4 pixelRotation4(uvec2 pixel, uint salt) {
  return vec4(pixelRotation(pixel, salt), pixelRotation(pixel, salt + 101u));
}

// Shirley-Chiu concentric map from the unit square to the unit disc (keeps strata).
vec2 concentricDisc(vec2 u) {
  vec2 p = 2.0 * u - 1.0;
  if (p.x == 0.0 && p.y == 0.0) return vec2(0.0);
  float r, phi;
  if (abs(p.x) > abs(p.y)) {
    r = p.x;
    phi = (kPi / 4.0) * (p.y / p.x);
  } else {
    r = p.y;
    phi = (kPi / 2.0) - (kPi / 4.0) * (p.x / p.y);
  }
  return r * vec2(cos(phi), sin(phi));
}

#endif
