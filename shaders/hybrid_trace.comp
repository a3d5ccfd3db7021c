// Selective ray trace of the hybrid (stage 4): thin-lens rays only for the pixels of the ray mask's
// work list, one thread per listed pixel, whose subgroup shares out its pixels' rays. Each hit is
// split between a near and a far layer by its circle of confusion (smoothly across the focus
// zone); per pixel the step writes the layers' average colours, the hit ratio (near rays / rays
// shot), the average far world position and the average near and far CoC, for the temporal
// accumulation and spatial reconstruction (stages 5 and 6).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_shuffle : require
#extension GL_KHR_shader_subgroup_shuffle_relative : require
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

// What a pixel's rays add up to: (near colour sum, near weight), (far colour sum, near |CoC| sum),
// (far position sum, far CoC sum).
struct LayerSums {
  vec4 near;
  vec4 far;
  vec4 farPosition;
};

LayerSums traceRay(uvec2 pixel, uint sampleIndex) {
  vec4 u = r4Sample(sampleIndex, pixelRotation4(pixel, kSequenceHybrid));
  vec3 origin;
  vec3 direction = thinLensRay(vec2(pixel) + u.xy, apertureSample(u.zw), origin);
  RaySample hit = traceCameraRay(origin, direction);
  float depth = min(dot(hit.position - frame.eye, frame.forward), kBackgroundDepth);
  float coc = pixelCoc(max(depth, 1e-3));
  float w = nearWeight(coc);
  return LayerSums(vec4(w * hit.radiance, w), vec4((1.0 - w) * hit.radiance, w * abs(coc)),
                   vec4((1.0 - w) * hit.position, (1.0 - w) * coc));
}

// The lane of the subgroup whose pixel's rays hold ray `ray` of the subgroup: the last one whose
// first ray is not beyond it (a lane without rays shares its first ray with the next lane). A
// binary search of as many steps in every lane, so that its shuffles run in uniform control flow.
uint ownerOfRay(uint ray, uint firstRay) {
  uint owner = 0u;
  for (uint step = gl_SubgroupSize / 2u; step > 0u; step /= 2u) {
    uint firstRayThere = subgroupShuffle(firstRay, owner + step);
    if (firstRayThere <= ray) owner += step;
  }
  return owner;
}

// Adds up each run of lanes with the same owner (owners do not decrease along the lanes): the
// last lane of a run ends with the run's sum.
LayerSums sumRuns(LayerSums sums, uint owner) {
  for (uint offset = 1u; offset < gl_SubgroupSize; offset *= 2u) {
    // Every lane shuffles: behind `&&` the lanes below offset would skip it, and a lane does not
    // read the value of one that skipped it.
    uint ownerBelow = subgroupShuffleUp(owner, offset);
    bool sameRun = gl_SubgroupInvocationID >= offset && ownerBelow == owner;
    vec4 near = subgroupShuffleUp(sums.near, offset);
    vec4 far = subgroupShuffleUp(sums.far, offset);
    vec4 farPosition = subgroupShuffleUp(sums.farPosition, offset);
    if (sameRun) {
      sums.near += near;
      sums.far += far;
      sums.farPosition += farPosition;
    }
  }
  return sums;
}

// The subgroup's rays are dealt out a ray per lane per round, in pixel order: a lane whose pixel
// asks for fewer rays does not idle while another's takes more (the work list's ray counts vary
// from 1 to the frame's samples). After each round the lanes holding a pixel's rays add them up
// and its lane takes the sum.
void main() {
  uint index = gl_GlobalInvocationID.x;
  bool listed = index < workList.header.count;
  uvec2 entry = listed ? workList.entries[index] : uvec2(0u);
  uvec2 pixel = unpackRayWorkPixel(entry.x);
  uint rays = listed ? max(entry.y, 1u) : 0u;
  uint firstSample = 0u;
  if (listed) {
    firstSample = imageLoad(samplesTraced, ivec2(pixel)).r;
    imageStore(samplesTraced, ivec2(pixel), uvec4(firstSample + rays));
  }
  uint firstRay = subgroupExclusiveAdd(rays);
  uint totalRays = subgroupAdd(rays);
  LayerSums own = LayerSums(vec4(0.0), vec4(0.0), vec4(0.0));
  for (uint round = 0u; round < totalRays; round += gl_SubgroupSize) {
    uint ray = round + gl_SubgroupInvocationID;
    uint owner = ownerOfRay(ray, firstRay);
    uint ownerPixel = subgroupShuffle(entry.x, owner);
    uint ownerSample = subgroupShuffle(firstSample, owner) + ray - subgroupShuffle(firstRay, owner);
    LayerSums sums = LayerSums(vec4(0.0), vec4(0.0), vec4(0.0));
    if (ray < totalRays)
      sums = traceRay(unpackRayWorkPixel(ownerPixel), ownerSample);
    else
      owner = gl_SubgroupSize;  // no ray: a run of its own that no lane reads
    sums = sumRuns(sums, owner);
    // The lane of this lane's pixel's last ray in the round, if its rays meet the round.
    bool inRound = rays > 0u && firstRay < round + gl_SubgroupSize && firstRay + rays > round;
    uint last = inRound ? min(firstRay + rays, round + gl_SubgroupSize) - 1u - round : 0u;
    vec4 near = subgroupShuffle(sums.near, last);
    vec4 far = subgroupShuffle(sums.far, last);
    vec4 farPosition = subgroupShuffle(sums.farPosition, last);
    if (inRound) {
      own.near += near;
      own.far += far;
      own.farPosition += farPosition;
    }
  }
  if (!listed) return;
  float nearWeightSum = own.near.w;
  float farWeightSum = float(rays) - nearWeightSum;
  float ratio = nearWeightSum / float(rays);
  ivec2 p = ivec2(pixel);
  vec3 nearColor = nearWeightSum > 0.0 ? own.near.rgb / nearWeightSum : vec3(0.0);
  vec3 farColor = farWeightSum > 0.0 ? own.far.rgb / farWeightSum : vec3(0.0);
  vec3 farMean = farWeightSum > 0.0 ? own.farPosition.xyz / farWeightSum : vec3(0.0);
  imageStore(nearLayer, p, vec4(nearColor, ratio));
  imageStore(farLayer, p, vec4(farColor, 1.0 - ratio));
  imageStore(farPosition, p, vec4(farMean, farWeightSum));
  imageStore(layerCoc, p, vec4(nearWeightSum > 0.0 ? own.far.w / nearWeightSum : 0.0,
                               farWeightSum > 0.0 ? own.farPosition.w / farWeightSum : 0.0, 0.0,
                               0.0));
}
