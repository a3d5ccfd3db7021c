// Set 1, binding 0: the frame uniforms every step reads, and what follows from them.
#ifndef HDOF_LIB_FRAME_GLSL
#define HDOF_LIB_FRAME_GLSL
#include "shared/frame.h"
#include "shared/math.h"

layout(set = 1, binding = kBindingFrame, std140) uniform Frame { FrameUniforms frame; };

// World-space width of one pixel per metre of distance from the camera.
float pixelAngle() { return 2.0 * frame.tanHalfFovY / float(frame.imageSize.y); }

float apertureRadius() { return 0.5 * frame.apertureDiameter; }

// The size of the steps' half-resolution images: half the frame's, rounded up. Sizes come from the
// frame, not from imageSize(), which may hold unused texels (gpu::ImageDesc::sidesOffPowerOfTwo).
ivec2 halfImageSize() { return (ivec2(frame.imageSize) + 1) / 2; }

// The signed circle of confusion, in pixels, of a point at linear view depth z (metres):
// negative in the near field.
float pixelCoc(float z) {
  return signedCocPixels(z, frame.apertureDiameter, frame.focusDistance, frame.focalLengthPixels);
}

// Camera and lens rest and the raster refines this view (rasterSample, stillFrames): a still
// view's frames, not a focus pull's, whose lens changes under a standing raster.
bool viewRests() { return frame.rasterSample > 0u && frame.stillFrames > 0u; }

// Relative luminance of linear Rec. 709 radiance.
float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// The 16-bit float nearest to v (its 13 low mantissa bits rounded off), which a 16-bit image then
// holds exactly: a device may convert to a 16-bit format by rounding towards zero (Vulkan allows
// it; lavapipe does), and the raster's running average, stored so, lost a fraction of a step
// every frame, which the later frames kept: a still view's 16 frames came out up to a sixth of an
// 8-bit level darker, with rings where smooth shading crossed a level.
vec3 nearestHalf(vec3 v) { return uintBitsToFloat((floatBitsToUint(v) + 0x1000u) & ~0x1fffu); }

#endif
