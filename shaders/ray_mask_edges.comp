// Ray mask (stage 3), edges (like Canny): a 3x3 Gaussian of the G-buffer, then a Sobel kernel,
// folded into one 5x5 derivative-of-Gaussian kernel per pixel. Normals take the Sobel gradient.
// Depth takes the second difference of inverse depth instead: a receding floor has a steep depth
// gradient, but its inverse depth is affine in screen space, so only real discontinuities remain;
// dividing by the nearest inverse depth makes the jump relative, so edges count at every distance.
// Only edges whose near side is out of focus need rays (partial occlusion), within that side's CoC
// radius: `reach` is that diameter (0: no rays needed), `strength` how strong the edge is and the
// |CoC| of its sharper side (how fine the detail its rays see can be: rays by CoC). A near side in
// the near field blurred wider than the post-process's largest blur (kDofMaxCoc) reaches as far
// as the lens blurs it (up to kRayMaskFarReach): only rays show what lies behind it there. In the
// far field only depth edges with a wide enough blur count: creases of a surface and small
// background blurs are the post-process's, except while the view rests, when every edge whose blur
// spans a pixel gets rays so that a still frame converges to the lens's image, and so do the
// pixels that an in-focus edge crosses: the raster's 16 frames of samples leave them short of the
// traced image's antialiasing.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"
#include "shared/ray_work.h"

layout(set = 1, binding = 1, rgba32f) uniform readonly image2D normalDepth;
layout(set = 1, binding = 2, r16f) uniform writeonly image2D reach;
layout(set = 1, binding = 3, rg16f) uniform writeonly image2D strength;

// The 3x3 Gaussian [1 2 1] / 4 convolved with Sobel's smoothing [1 2 1] / 4, with Sobel's
// central difference [-1 0 1] / 2, and with the second difference [1 -2 1].
float smoothing(int i) { return float(6 - 2 * abs(i) - int(abs(i) == 2)) / 16.0; }
float derivative(int i) { return float(sign(i) * (3 - abs(i))) / 8.0; }
float secondDifference(int i) { return float(abs(i) == 2 ? 1 : abs(i) == 1 ? 0 : -2) / 4.0; }

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(frame.imageSize);
  if (any(greaterThanEqual(pixel, size))) return;
  vec3 normalDx = vec3(0.0), normalDy = vec3(0.0);
  float inverseDxx = 0.0, inverseDyy = 0.0;
  float nearestInverse = 0.0;  // the near side of any edge the kernel sees
  float farthestInverse = 1e4;  // and its far side
  // The same over the pixel's 3x3 neighbourhood, and the normals' least agreement with its own.
  float innerNearest = 0.0, innerFarthest = 1e4, innerNormals = 1.0;
  vec3 ownNormal = imageLoad(normalDepth, pixel).xyz;
  [[unroll]] for (int dy = -2; dy <= 2; ++dy) {
    [[unroll]] for (int dx = -2; dx <= 2; ++dx) {
      vec4 texel = imageLoad(normalDepth, clamp(pixel + ivec2(dx, dy), ivec2(0), size - 1));
      float inverseDepth = 1.0 / max(texel.w, 1e-4);
      if (abs(dx) <= 1 && abs(dy) <= 1) {
        innerNearest = max(innerNearest, inverseDepth);
        innerFarthest = min(innerFarthest, inverseDepth);
        innerNormals = min(innerNormals, dot(texel.xyz, ownNormal));
      }
      normalDx += derivative(dx) * smoothing(dy) * texel.xyz;
      normalDy += smoothing(dx) * derivative(dy) * texel.xyz;
      inverseDxx += secondDifference(dx) * smoothing(dy) * inverseDepth;
      inverseDyy += smoothing(dx) * secondDifference(dy) * inverseDepth;
      nearestInverse = max(nearestInverse, inverseDepth);
      farthestInverse = min(farthestInverse, inverseDepth);
    }
  }
  // A step of relative height j gives a second difference of j / 4 next to it.
  float depthJump = 4.0 * max(abs(inverseDxx), abs(inverseDyy)) / nearestInverse;
  float normalGradient = sqrt(dot(normalDx, normalDx) + dot(normalDy, normalDy));
  float depthEdge = smoothstep(kRayMaskDepthJumpLow, kRayMaskDepthJumpHigh, depthJump);
  float normalEdge = smoothstep(kRayMaskNormalLow, kRayMaskNormalHigh, normalGradient);
  float nearSideCoc = signedCoc(1.0 / nearestInverse);
  float nearCoc = abs(nearSideCoc);
  float nearBlur = abs(pixelCoc(1.0 / nearestInverse));  // not clamped to the post-process's
  float edge = nearSideCoc < 0.0 ? max(depthEdge, normalEdge)
                                 : (nearCoc >= kRayMaskFarEdgeCoc ? depthEdge : 0.0);
  // The band the kernel marks is 2 px to each side of the true edge; the margin keeps rays over
  // the whole blur of the near side from any pixel of the band.
  bool needsRays = edge > 0.0 && nearCoc >= kDofFocusZone;
  float diameter = !needsRays            ? 0.0
                   : nearSideCoc < 0.0 ? min(nearBlur + 2.0, kRayMaskFarReach)
                                       : min(nearCoc + 2.0, kDofMaxCoc);
  // An in-focus silhouette over a blurred background: the background beside it is partly hidden
  // behind it for the lens, and the silhouette's own pixels mix it with that blur. Rays over
  // the background's blur radius from the edge, at most kRayMaskSilhouetteReach.
  float farCoc = signedCoc(1.0 / farthestInverse);
  if (!needsRays && depthEdge > 0.0 && nearCoc < kDofFocusZone && farCoc >= kRayMaskFarEdgeCoc) {
    needsRays = true;
    edge = depthEdge;
    diameter = min(farCoc, kRayMaskSilhouetteReach) + 2.0;
  }
  // While the view rests (camera and lens; not in a focus pull, whose few rays a pixel would not
  // hand over), every edge whose blur spans a pixel: the post-process's small blurs are
  // approximate there, and only rays converge to the lens's image.
  float wider = max(nearCoc, abs(farCoc));
  if (!needsRays && viewRests() && max(depthEdge, normalEdge) > 0.0 && wider >= 1.0) {
    needsRays = true;
    edge = max(depthEdge, normalEdge);
    diameter = min(wider, kRayMaskSilhouetteReach) + 2.0;
  }
  // ... and the pixels that an in-focus edge crosses (a depth or normal step within the 3x3),
  // alone: the composite hands them over to their traced colour as its rays add up.
  bool crossed = innerNearest > innerFarthest * (1.0 + kRayMaskDepthJumpLow) ||
                 innerNormals < kRayMaskCrossedNormal;
  if (!needsRays && viewRests() && max(depthEdge, normalEdge) > 0.0 && crossed) {
    needsRays = true;
    edge = max(depthEdge, normalEdge);
    diameter = 1.0;
  }
  imageStore(reach, pixel, vec4(diameter));
  imageStore(strength, pixel, vec4(needsRays ? edge : 0.0, min(nearCoc, abs(farCoc)), 0.0, 0.0));
}
