// G-buffer (stage 1), resolve step (timed as gbuffer): for the triangle the raster found at each
// sample, the point the ray through the sample's position hits, shaded with the shared shading
// function: sharp colour, its specular part, normal and linear depth, and the motion vector. The
// same ray through the same triangle gives the ray tracer's point. A frame after a cut samples
// pixel centres, one in motion a jittered position (the anti-aliasing's reprojected history
// gathers them); both write everything. A still view's later frames write only colour and
// specular, so that depth, normals and the CoC the DoF steps derive from them hold still, and a
// zero motion (the view has not moved).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/scene.glsl"
#include "lib/frame.glsl"
#include "lib/dof.glsl"
#include "lib/shading.glsl"
#include "lib/camera_rays.glsl"
#include "shared/ray_work.h"
#include "lib/skippable.glsl"

// Which step this pipeline runs (gbuffer_pass.cpp picks): kOneSample, a frame after a cut or in
// motion; kFirstTriangle and kOtherTriangles, a still view's later frames, whose
// kStillRasterSamples samples per pixel the multisampled raster found: the first triangle among a
// pixel's samples for every pixel, then the others for the pixels it listed (sharedPixels), which
// are few.
const uint kOneSample = 0, kFirstTriangle = 1, kOtherTriangles = 2;
layout(constant_id = 0) const uint kStep = kOneSample;

// The triangles' numbers as floats (gbuffer.frag), -1 where there is none.
layout(set = 1, binding = 1, r32f) uniform readonly image2D visibility;
layout(set = 1, binding = 2) uniform sampler2DMS multisampledVisibility;
layout(set = 1, binding = 3, rgba16f) uniform image2D outColor;  // a: the first sample's CoC
// a: what the frame's sample counts for in the average (antialias.comp): 1, or
// kStillRasterSamples where the samples saw several triangles.
layout(set = 1, binding = 4, rgba16f) uniform image2D outSpecular;
layout(set = 1, binding = 5) uniform writeonly image2D outNormalDepth;  // rgba32f
layout(set = 1, binding = 6) uniform writeonly image2D outMotion;  // rg16f
HDOF_RAY_WORK_LIST(7, coherent);  // sharedPixels

const uint kNoTriangle = 0xffffffffu;

uint triangleNumber(float visible) { return visible < 0.0 ? kNoTriangle : uint(visible); }

const float kFootprintScale = 2.0;

// Vulkan's standard positions of 4 samples in a pixel, from its corner.
const vec2 kSamplePositions[4] =
    vec2[4](vec2(0.375, 0.125), vec2(0.875, 0.375), vec2(0.125, 0.625), vec2(0.625, 0.875));

// What the ray through an image position (in pixels from the image's corner) sees on a triangle
// (kNoTriangle: the sky). point: the surface point (w = 1) or the sky's direction (w = 0).
struct Sample {
  vec3 color, specular, normal;
  float linearDepth;
  vec4 point;
};

Sample shade(uint triangle, vec2 position) {
  vec3 direction = pinholeDirection(position);
  if (triangle == kNoTriangle)
    return Sample(frame.skyColor, vec3(0.0), vec3(0.0), kBackgroundDepth, vec4(direction, 0.0));
  // Barycentrics of the ray on the plane of the triangle (Möller–Trumbore without the inside
  // test: the raster already decided coverage).
  uvec4 corners = sceneTriangle(triangle);
  vec3 a = vertexPosition(corners.x);
  vec3 edge1 = vertexPosition(corners.y) - a;
  vec3 edge2 = vertexPosition(corners.z) - a;
  vec3 p = cross(direction, edge2);
  float det = dot(edge1, p);
  float inverseDet = abs(det) > 1e-20 ? 1.0 / det : 0.0;
  vec3 toOrigin = frame.eye - a;
  vec2 barycentrics =
      vec2(dot(toOrigin, p), dot(direction, cross(toOrigin, edge1))) * inverseDet;
  barycentrics = clamp(barycentrics, 0.0, 1.0);
  barycentrics /= max(1.0, barycentrics.x + barycentrics.y);
  SurfacePoint s = surfaceOfTriangle(triangle, barycentrics);
  vec3 toEye = frame.eye - s.position;
  float distance = length(toEye);
  Sample result;
  result.color = shadeSurface(s, toEye / distance, distance * pixelAngle(), result.specular);
  result.normal = normalize(s.normal);
  result.linearDepth = dot(s.position - frame.eye, frame.forward);
  result.point = vec4(s.position, 1.0);
  return result;
}

// Offset in pixels from this pixel's centre to where the surface there was on screen in the
// previous frame, from the point (w = 1) or direction (w = 0) the jittered sample found: the
// sample lies rasterJitter from the centre, and so did its point before.
vec2 motionTo(vec4 point, ivec2 pixel) {
  vec4 clip = frame.previousViewProj * point;
  vec2 previous = (clip.xy / clip.w * 0.5 + 0.5) * vec2(frame.imageSize);
  return previous - (vec2(pixel) + 0.5 + frame.rasterJitter);
}

// A still view's multisampled frames: a pixel's kStillRasterSamples samples. The raster moves the
// standard pattern by the frame's jitter, so that a sample of another pixel can lie in this one's
// square: each of the pattern's samples is taken from the pixel whose moved sample falls in this
// square (there is one), and the pixel's samples are always kStillRasterSamples points of its own
// square, however far the jitter moves the pattern. Where they all see one triangle, it is shaded
// at the first sample (a jittered sample as a single-sampled frame's, so that texture detail
// averages as the jitter moves it); else each triangle among them once, at the mean position of
// its samples, weighted by their share.
struct PixelSamples {
  uint triangles[4];
  vec2 positions[4];
};

PixelSamples samplesOf(ivec2 pixel) {
  ivec2 last = ivec2(frame.imageSize) - 1;
  PixelSamples samples;
  for (int k = 0; k < 4; ++k) {
    vec2 moved = kSamplePositions[k] + frame.rasterJitter;
    ivec2 source = clamp(pixel - ivec2(floor(moved)), ivec2(0), last);
    samples.triangles[k] = triangleNumber(texelFetch(multisampledVisibility, source, k).r);
    samples.positions[k] = vec2(source) + moved;
  }
  return samples;
}

// The mean position of the pixel's samples that see sample k's triangle, and their share of the
// pixel.
vec2 meanPosition(PixelSamples samples, int k, out float share) {
  vec2 sum = vec2(0.0);
  share = 0.0;
  for (int j = 0; j < 4; ++j) {
    bool same = samples.triangles[j] == samples.triangles[k];
    sum += same ? samples.positions[j] : vec2(0.0);
    share += same ? 0.25 : 0.0;
  }
  return sum / (4.0 * share);
}

// kFirstTriangle: the first sample's triangle, and the pixel listed when its samples see others.
void resolveFirstTriangle(ivec2 pixel, bool inside) {
  bool listed = false;
  if (inside) {
    PixelSamples samples = samplesOf(pixel);
    float share;
    vec2 mean = meanPosition(samples, 0, share);
    listed = share < 1.0;
    Sample s = shade(samples.triangles[0], listed ? mean : samples.positions[0]);
    float counts = listed ? float(kStillRasterSamples) : 1.0;
    imageStore(outColor, pixel, vec4(nearestHalf(share * s.color), signedCoc(s.linearDepth)));
    imageStore(outSpecular, pixel, vec4(share * s.specular, counts));
    imageStore(outMotion, pixel, vec4(0.0));
  }
  uvec4 ballot = subgroupBallot(listed);
  uint count = subgroupBallotBitCount(ballot);
  uint first = 0u;
  if (subgroupElect() && count > 0u) first = atomicAdd(workList.header.count, count);
  first = subgroupBroadcastFirst(first);
  if (listed)
    workList.entries[first + subgroupBallotExclusiveBitCount(ballot)] =
        uvec2(packRayWorkPixel(uint(pixel.x), uint(pixel.y)), 0u);
}

// kOtherTriangles: a listed pixel's other triangles, added to the first one's share.
void resolveOtherTriangles(uint index) {
  if (index >= workList.header.count) return;
  ivec2 pixel = ivec2(unpackRayWorkPixel(workList.entries[index].x));
  PixelSamples samples = samplesOf(pixel);
  vec3 color = vec3(0.0), specular = vec3(0.0);
  for (int k = 1; k < 4; ++k) {
    bool counted = false;
    for (int j = 0; j < k; ++j) counted = counted || samples.triangles[j] == samples.triangles[k];
    SKIPPABLE_IF(!counted) {
      float share;
      Sample s = shade(samples.triangles[k], meanPosition(samples, k, share));
      color += share * s.color;
      specular += share * s.specular;
    }
  }
  vec4 firstColor = imageLoad(outColor, pixel);
  imageStore(outColor, pixel, vec4(nearestHalf(firstColor.rgb + color), firstColor.a));
  vec4 firstSpecular = imageLoad(outSpecular, pixel);
  imageStore(outSpecular, pixel, vec4(firstSpecular.rgb + specular, firstSpecular.a));
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  bool inside = all(lessThan(uvec2(pixel), frame.imageSize));
  if (kStep == kFirstTriangle) {
    resolveFirstTriangle(pixel, inside);
    return;
  }
  if (kStep == kOtherTriangles) {
    resolveOtherTriangles(gl_WorkGroupID.x * kRayWorkGroupSize + gl_LocalInvocationIndex);
    return;
  }
  if (!inside) return;
  vec2 position = vec2(pixel) + 0.5 + frame.rasterJitter;
  Sample s = shade(triangleNumber(imageLoad(visibility, pixel).r), position);
  imageStore(outColor, pixel, vec4(nearestHalf(s.color), signedCoc(s.linearDepth)));
  imageStore(outSpecular, pixel, vec4(s.specular, 1.0));
  if (frame.rasterSample > 0u) {
    imageStore(outMotion, pixel, vec4(0.0));
    return;
  }
  imageStore(outNormalDepth, pixel, vec4(s.normal, s.linearDepth));
  imageStore(outMotion, pixel, vec4(motionTo(s.point, pixel), 0.0, 0.0));
}
