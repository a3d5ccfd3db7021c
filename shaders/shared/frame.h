// Per-frame uniforms (camera, lens, image, lighting environment) and the thin-lens
// circle-of-confusion formula, shared by C++ and every shader.
#ifndef HDOF_SHARED_FRAME_H
#define HDOF_SHARED_FRAME_H
#include "types.h"

HDOF_NAMESPACE_BEGIN

// Descriptor set 1: per pass. Binding 0 is always the frame uniforms.
HDOF_CONST uint kPassSet = 1;
HDOF_CONST uint kBindingFrame = 0;

// Linear depth written where no surface is (the sky), in metres.
HDOF_CONST float kBackgroundDepth = 1.0e5;

struct FrameUniforms {
  mat4 viewProj;  // world to clip, Vulkan conventions (y down, depth 0..1)
  mat4 previousViewProj;  // the previous frame's (this frame's after a cut): motion vectors
  vec4 eye;       // xyz camera position, w tan(vertical fov / 2)
  vec4 right;     // xyz unit right vector, w tan(horizontal fov / 2)
  vec4 up;        // xyz unit up vector, w aperture diameter in metres (focal length / f-number)
  vec4 forward;   // xyz unit view direction, w focus distance in metres
  vec4 lens;  // x focal length in pixels (width / 2 tan(hfov/2)), y focal length (m), z f-number,
              // w aperture blade count (0: circle)
  vec4 lensShape;    // x blade rotation (radians), yzw unused
  vec4 skyColor;     // ambient light from above (linear RGB), w exposure
  vec4 groundColor;  // ambient light from below, w unused
  uvec4 image;  // x width, y height, z frame index (for sampling sequences), w samples per pixel
  // x light count, y pixel jitter on (1) or rays through pixel centres (0), zw unused
  uvec4 options;
};

// Signed circle of confusion, in pixels, of a point at linear view depth z (metres along the view
// axis): negative in front of the focus plane (near field), positive behind it (far field).
// Thin lens (Potmesil 1982): on a sensor the CoC is A |z - S| / z * f / (S - f); the sensor width
// that the field of view implies at focus distance S is 2 tan(hfov/2) f S / (S - f), so in pixels
// it reduces to A (z - S) / (z S) times the focal length in pixels. For a 36 mm sensor and a field
// of view that matches the focal length this is exactly the sensor formula times width / 36 mm.
HDOF_FN float signedCocPixels(float z, float apertureDiameter, float focusDistance,
                              float focalLengthPixels) {
  return apertureDiameter * focalLengthPixels * (z - focusDistance) / (z * focusDistance);
}

// The sensor-plane CoC diameter (same units as the focal length) for a sensor-based check.
HDOF_FN float cocOnSensor(float z, float focalLength, float fNumber, float focusDistance) {
  float aperture = focalLength / fNumber;
  return aperture * abs(z - focusDistance) / z * focalLength / (focusDistance - focalLength);
}

HDOF_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(hdof::gpu::FrameUniforms) == 2 * 64 + 10 * 16);
#endif

#endif
