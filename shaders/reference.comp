// The one step of the raytrace and reference modes (in place of stages 1 to 7, timed under the
// mode's name): thin-lens ray tracing over the whole frame, accumulated progressively: each
// dispatch adds sampleCount rays per pixel to a running sum (alpha counts the rays). The ground
// truth that the other modes are measured against.
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/scene.glsl"
#include "lib/frame.glsl"
#include "lib/shading.glsl"
#include "lib/bvh_traverse.glsl"
#include "lib/ray_shading.glsl"
#include "lib/sampling.glsl"
#include "lib/camera_rays.glsl"

layout(set = 1, binding = 1, rgba32f) uniform image2D accumulation;

layout(push_constant) uniform Push { RayTraceRays push; };

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, frame.imageSize))) return;
  vec4 rotation = pixelRotation4(pixel, push.sequence);
  bool jitter = frame.pixelJitter != 0u;
  vec3 sum = vec3(0.0);
  for (uint i = 0u; i < push.sampleCount; ++i) {
    vec4 u = r4Sample(push.firstSample + i, rotation);
    vec2 position = vec2(pixel) + (jitter ? u.xy : vec2(0.5));
    vec3 origin;
    vec3 direction = thinLensRay(position, apertureSample(u.zw), origin);
    sum += traceCameraRay(origin, direction).radiance;
  }
  vec4 previous = push.accumulate == 0u ? vec4(0.0) : imageLoad(accumulation, ivec2(pixel));
  imageStore(accumulation, ivec2(pixel), previous + vec4(sum, float(push.sampleCount)));
}
