// Thin-lens camera rays (Potmesil 1982): a ray from a point on the lens through the point of the
// focus plane that the pixel sees. Needs lib/frame.glsl.
#ifndef HDOF_LIB_CAMERA_RAYS_GLSL
#define HDOF_LIB_CAMERA_RAYS_GLSL
#include "lib/sampling.glsl"

// Direction through the camera centre for image position `pixel` (pixels, y down; pixel centres
// at +0.5); its component along the view axis is 1.
vec3 pinholeDirection(vec2 pixel) {
  vec2 ndc = pixel / vec2(frame.imageSize) * 2.0 - 1.0;
  return frame.forward + ndc.x * frame.tanHalfFovX * frame.right -
         ndc.y * frame.tanHalfFovY * frame.up;
}

// A point of the aperture from a point of the unit square, uniform over its area: the unit disc,
// or with blades a regular polygon inscribed in it with one vertex at the blade rotation
// (counter-clockwise from the camera's right). The post-process kernel uses the same polygon.
vec2 apertureSample(vec2 u) {
  float blades = frame.bladeCount;
  if (blades < 3.0) return concentricDisc(u);
  float sector = 2.0 * kPi / blades;
  float scaled = u.x * blades;
  float k = min(floor(scaled), blades - 1.0);
  float a = frame.bladeRotation + k * sector;
  vec2 v0 = vec2(cos(a), sin(a)), v1 = vec2(cos(a + sector), sin(a + sector));
  // Uniform in the triangle (centre, v0, v1): the square root spreads the radius by area.
  float radial = sqrt(scaled - k);
  return radial * mix(v0, v1, u.y);
}

// lensSample: a point of the unit disc (see apertureSample). Writes the ray origin; returns the unit direction.
vec3 thinLensRay(vec2 pixel, vec2 lensSample, out vec3 origin) {
  vec3 focusPoint = frame.eye + pinholeDirection(pixel) * frame.focusDistance;
  vec2 offset = lensSample * apertureRadius();
  origin = frame.eye + offset.x * frame.right + offset.y * frame.up;
  return normalize(focusPoint - origin);
}

#endif
