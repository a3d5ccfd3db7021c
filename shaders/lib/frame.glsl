// Set 1, binding 0: the frame uniforms every pass reads.
#ifndef HDOF_LIB_FRAME_GLSL
#define HDOF_LIB_FRAME_GLSL
#include "shared/frame.h"

layout(set = 1, binding = kBindingFrame, std140) uniform Frame { FrameUniforms frame; };

// World-space width of one pixel per metre of distance from the camera.
float pixelAngle() { return 2.0 * frame.eye.w / float(frame.image.y); }

// Relative luminance of linear Rec. 709 radiance.
float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

#endif
