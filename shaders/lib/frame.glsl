// Set 1, binding 0: the frame uniforms every step reads, and what follows from them.
#ifndef HDOF_LIB_FRAME_GLSL
#define HDOF_LIB_FRAME_GLSL
#include "shared/frame.h"
#include "shared/math.h"

layout(set = 1, binding = kBindingFrame, std140) uniform Frame { FrameUniforms frame; };

// World-space width of one pixel per metre of distance from the camera.
float pixelAngle() { return 2.0 * frame.tanHalfFovY / float(frame.imageSize.y); }

float apertureRadius() { return 0.5 * frame.apertureDiameter; }

// The signed circle of confusion, in pixels, of a point at linear view depth z (metres):
// negative in the near field.
float pixelCoc(float z) {
  return signedCocPixels(z, frame.apertureDiameter, frame.focusDistance, frame.focalLengthPixels);
}

// Relative luminance of linear Rec. 709 radiance.
float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

#endif
