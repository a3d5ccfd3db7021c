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

// std140 and C++ agree without padding fields: every vec3 is followed by a scalar.
struct FrameUniforms {
  mat4 viewProj;          // world to clip, Vulkan conventions (y down, depth 0..1)
  mat4 previousViewProj;  // the previous frame's (this frame's after a cut): motion vectors
  vec3 eye;               // camera position
  float tanHalfFovY;
  vec3 right;  // unit right vector
  float tanHalfFovX;
  vec3 up;                 // unit up vector
  float apertureDiameter;  // metres: focal length / f-number
  vec3 forward;            // unit view direction
  float focusDistance;     // metres along forward
  float focalLengthPixels;  // width / (2 tan(hfov / 2))
  float focalLength;        // metres
  float fNumber;
  float bladeCount;     // aperture blades, 0: a circle
  float bladeRotation;  // radians
  // The raster's anti-aliasing: how many samples of this view the G-buffer has accumulated before
  // this frame's (0: a new view, sampled at pixel centres), and this frame's sample position as
  // an offset from the pixel centre, in pixels.
  uint rasterSample;
  vec2 rasterJitter;
  vec3 skyColor;  // ambient light from above (linear RGB)
  float exposure;
  vec3 groundColor;  // ambient light from below
  float acceptableCoc;  // metres on the sensor: the circle of confusion accepted as sharp
  uvec2 imageSize;       // pixels
  uint frameIndex;       // for sampling sequences
  uint samplesPerPixel;  // rays per pixel this frame
  uint lightCount;
  uint pixelJitter;  // 1: rays jittered over the pixel, 0: through pixel centres
  // Frames of this camera and lens before this one (0: a new view, or the lens just changed): a
  // focus pull on a still view has a standing raster (rasterSample) but no resting rays.
  uint stillFrames;
  // The camera's near clipping plane, metres along the view axis: the raster draws nothing in
  // front of it, and camera rays hit nothing in front of it either.
  float znear;
};

// Which family of per-pixel sample sequences a ray tracer draws from (the salt of
// pixelRotation4 in lib/sampling.glsl): modes never share rays.
HDOF_CONST uint kSequenceReference = 0;
HDOF_CONST uint kSequenceRayTrace = 1;
HDOF_CONST uint kSequenceHybrid = 2;

// A still view's raster runs this many frames (the pixel centre, then the jitter sequence) and
// averages their samples; then it stands: later frames of the view, lens changes among them, reuse
// its G-buffer and run only what follows it.
HDOF_CONST uint kStillRasterFrames = 16;
// The first kMultisampledFrames frames of a still view after the first raster kStillRasterSamples
// samples per pixel (the standard pattern, moved by the frame's jitter): a pixel whose samples see
// one triangle is shaded once, at one of them, and counts as a sample; one whose samples see
// several counts as kStillRasterSamples (its edges converge that much faster). Every other frame
// takes one sample.
HDOF_CONST uint kMultisampledFrames = 3;
HDOF_CONST uint kStillRasterSamples = 4;

// Push constants of reference.comp (the reference and raytrace modes).
struct RayTraceRays {
  uint firstSample;  // number of the first ray of each pixel's sequence traced here
  uint sampleCount;  // rays per pixel
  uint accumulate;   // 1: add to the accumulation, 0: start a new sum
  uint sequence;     // kSequence*
};

// Signed circle of confusion, in pixels, of a point at linear view depth z (metres along the view
// axis): negative in front of the focus plane (near field), positive behind it (far field).
// The thin-lens rays see the focus plane S through a field of view that does not change with focus
// (the lens's at infinity, render/lens_optics.h), so a blur of A |z - S| / z on that plane is
// A (z - S) / (z S) times the focal length in pixels. On a sensor (Potmesil 1982) the CoC is
// A |z - S| / z * f / (S - f), the same times width / sensor width except for the factor
// S / (S - f) that focus breathing would bring (2 % at 2.4 m with 50 mm).
HDOF_FN float signedCocPixels(float z, float apertureDiameter, float focusDistance,
                              float focalLengthPixels) {
  return apertureDiameter * focalLengthPixels * (z - focusDistance) / (z * focusDistance);
}

// The sensor-plane CoC diameter (same units as the focal length): what the depth of field's
// near and far limits (render/lens_optics.h) compare with the acceptable circle.
HDOF_FN float cocOnSensor(float z, float focalLength, float fNumber, float focusDistance) {
  float aperture = focalLength / fNumber;
  return aperture * abs(z - focusDistance) / z * focalLength / (focusDistance - focalLength);
}

HDOF_NAMESPACE_END

#ifdef __cplusplus
#include <cstddef>
static_assert(sizeof(hdof::gpu::FrameUniforms) == 2 * 64 + 10 * 16);
static_assert(offsetof(hdof::gpu::FrameUniforms, tanHalfFovY) == 128 + 12);
static_assert(offsetof(hdof::gpu::FrameUniforms, focusDistance) == 128 + 3 * 16 + 12);
static_assert(offsetof(hdof::gpu::FrameUniforms, focalLengthPixels) == 128 + 4 * 16);
static_assert(offsetof(hdof::gpu::FrameUniforms, exposure) == 128 + 6 * 16 + 12);
static_assert(offsetof(hdof::gpu::FrameUniforms, imageSize) == 128 + 8 * 16);
static_assert(offsetof(hdof::gpu::FrameUniforms, lightCount) == 128 + 9 * 16);
static_assert(offsetof(hdof::gpu::FrameUniforms, rasterJitter) == 128 + 5 * 16 + 8);
static_assert(sizeof(hdof::gpu::RayTraceRays) == 16);
#endif

#endif
