// Selective ray trace of the hybrid (stage 4): thin-lens rays only for the pixels of the ray mask's
// work list, one thread per listed pixel. Each hit is split between a near and a far layer by its
// circle of confusion (smoothly across the focus zone); per pixel the step writes the layers'
// average colours, the hit ratio (near rays / rays shot), the average far world position and the
// average near and far CoC, for the temporal accumulation and spatial reconstruction (stages 5 and
// 6).
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;

#include "lib/scene.glsl"
#include "lib/frame.glsl"
#include "lib/shading.glsl"
#include "lib/bvh_traverse.glsl"
#include "lib/ray_shading.glsl"
#include "lib/camera_rays.glsl"
#include "shared/dof.h"
#include "shared/ray_work.h"

HDOF_RAY_WORK_LIST(1, readonly);
layout(set = 1, binding = 2) uniform writeonly image2D nearLayer;  // rgba16f: colour, hit ratio
layout(set = 1, binding = 3) uniform writeonly image2D farLayer;  // rgba16f: colour, 1 - ratio
layout(set = 1, binding = 4) uniform writeonly image2D farPosition;  // rgba32f: xyz, w far hits
layout(set = 1, binding = 5) uniform writeonly image2D layerCoc;  // rg16f: near |CoC|, far CoC
// Rays traced so far per pixel: where this frame's rays continue the pixel's sample sequence.
layout(set = 1, binding = 6, r32ui) uniform uimage2D samplesTraced;

// How much of a hit belongs to the near layer: all of it in front of the focus zone, none of it
// behind, linearly across the zone (|CoC| < kDofFocusZone), so the split has no seam.
float nearWeight(float coc) { return clamp(0.5 - coc / (2.0 * kDofFocusZone), 0.0, 1.0); }

void main() {
  if (gl_GlobalInvocationID.x >= workList.header.count) return;
  uvec2 entry = workList.entries[gl_GlobalInvocationID.x];
  uvec2 pixel = unpackRayWorkPixel(entry.x);
  uint rays = max(entry.y, 1u);
  vec4 rotation = pixelRotation4(pixel, kSequenceHybrid);
  uint firstSample = imageLoad(samplesTraced, ivec2(pixel)).r;
  imageStore(samplesTraced, ivec2(pixel), uvec4(firstSample + rays));
  vec3 nearSum = vec3(0.0), farSum = vec3(0.0), farPositionSum = vec3(0.0);
  float nearWeightSum = 0.0, nearCocSum = 0.0, farCocSum = 0.0;
  for (uint i = 0u; i < rays; ++i) {
    vec4 u = r4Sample(firstSample + i, rotation);
    vec3 origin;
    vec3 direction = thinLensRay(vec2(pixel) + u.xy, apertureSample(u.zw), origin);
    RaySample hit = traceCameraRay(origin, direction);
    float depth = min(dot(hit.position - frame.eye, frame.forward), kBackgroundDepth);
    float coc = pixelCoc(max(depth, 1e-3));
    float w = nearWeight(coc);
    nearSum += w * hit.radiance;
    farSum += (1.0 - w) * hit.radiance;
    farPositionSum += (1.0 - w) * hit.position;
    nearWeightSum += w;
    nearCocSum += w * abs(coc);
    farCocSum += (1.0 - w) * coc;
  }
  float farWeightSum = float(rays) - nearWeightSum;
  float ratio = nearWeightSum / float(rays);
  ivec2 p = ivec2(pixel);
  imageStore(nearLayer, p, vec4(nearWeightSum > 0.0 ? nearSum / nearWeightSum : vec3(0.0), ratio));
  imageStore(farLayer, p, vec4(farWeightSum > 0.0 ? farSum / farWeightSum : vec3(0.0), 1.0 - ratio));
  imageStore(farPosition, p, vec4(farWeightSum > 0.0 ? farPositionSum / farWeightSum : vec3(0.0),
                                  farWeightSum));
  imageStore(layerCoc, p, vec4(nearWeightSum > 0.0 ? nearCocSum / nearWeightSum : 0.0,
                               farWeightSum > 0.0 ? farCocSum / farWeightSum : 0.0, 0.0, 0.0));
}
