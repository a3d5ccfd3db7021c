// Thin-lens camera rays (Potmesil 1982): a ray from a point on the lens through the point of the
// focus plane that the pixel sees. Needs lib/frame.glsl.
#ifndef HDOF_LIB_CAMERA_RAYS_GLSL
#define HDOF_LIB_CAMERA_RAYS_GLSL

// Direction through the camera centre for image position `pixel` (pixels, y down; pixel centres
// at +0.5); its component along the view axis is 1.
vec3 pinholeDirection(vec2 pixel) {
  vec2 ndc = pixel / vec2(frame.image.xy) * 2.0 - 1.0;
  return frame.forward.xyz + ndc.x * frame.right.w * frame.right.xyz -
         ndc.y * frame.eye.w * frame.up.xyz;
}

// lensSample: a point of the unit disc. Writes the ray origin; returns the unit direction.
vec3 thinLensRay(vec2 pixel, vec2 lensSample, out vec3 origin) {
  vec3 focusPoint = frame.eye.xyz + pinholeDirection(pixel) * frame.forward.w;
  vec2 offset = lensSample * (0.5 * frame.up.w);
  origin = frame.eye.xyz + offset.x * frame.right.xyz + offset.y * frame.up.xyz;
  return normalize(focusPoint - origin);
}

#endif
