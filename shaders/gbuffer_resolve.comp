// G-buffer (stage 1), resolve step (timed as gbuffer): for the triangle the raster found at each
// pixel, the point the ray through the raster's sample position hits, shaded with the shared
// shading function: sharp colour, its specular part, normal and linear depth, and the motion
// vector. The same ray through the same triangle gives the ray tracer's point. A frame after a cut
// samples pixel centres, one in motion a jittered position (the anti-aliasing's reprojected
// history gathers them); both write everything. A still view's later frames (jittered samples)
// write only colour and specular, so that depth, normals and the CoC the DoF steps derive from
// them hold still, and a zero motion (the view has not moved).
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/scene.glsl"
#include "lib/frame.glsl"
#include "lib/dof.glsl"
#include "lib/shading.glsl"
#include "lib/camera_rays.glsl"

layout(set = 1, binding = 1, r32ui) uniform readonly uimage2D visibility;
layout(set = 1, binding = 2) uniform writeonly image2D outColor;  // rgba16f; a: the sample's CoC
layout(set = 1, binding = 3) uniform writeonly image2D outSpecular;  // rgba16f
layout(set = 1, binding = 4) uniform writeonly image2D outNormalDepth;  // rgba32f
layout(set = 1, binding = 5) uniform writeonly image2D outMotion;  // rg16f

// Offset in pixels from this pixel's centre to where the surface there was on screen in the
// previous frame, from the point (w = 1) or direction (w = 0) the jittered sample found: the
// sample lies rasterJitter from the centre, and so did its point before.
vec2 motionTo(vec4 point, ivec2 pixel) {
  vec4 clip = frame.previousViewProj * point;
  vec2 previous = (clip.xy / clip.w * 0.5 + 0.5) * vec2(frame.imageSize);
  return previous - (vec2(pixel) + 0.5 + frame.rasterJitter);
}

const uint kNoTriangle = 0xffffffffu;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(uvec2(pixel), frame.imageSize))) return;
  uint triangle = imageLoad(visibility, pixel).r;
  bool firstSample = frame.rasterSample == 0u;
  if (!firstSample) imageStore(outMotion, pixel, vec4(0.0));
  if (triangle == kNoTriangle) {
    imageStore(outColor, pixel, vec4(frame.skyColor, signedCoc(kBackgroundDepth)));
    imageStore(outSpecular, pixel, vec4(0.0));
    if (!firstSample) return;
    imageStore(outNormalDepth, pixel, vec4(0.0, 0.0, 0.0, kBackgroundDepth));
    vec2 position = vec2(pixel) + 0.5 + frame.rasterJitter;
    imageStore(outMotion, pixel, vec4(motionTo(vec4(pinholeDirection(position), 0.0),
                                               pixel), 0.0, 0.0));
    return;
  }
  // Barycentrics of the pixel centre's ray on the plane of the triangle (Möller–Trumbore
  // without the inside test: the raster already decided coverage).
  uvec4 corners = sceneTriangle(triangle);
  vec3 a = vertexPosition(corners.x);
  vec3 edge1 = vertexPosition(corners.y) - a;
  vec3 edge2 = vertexPosition(corners.z) - a;
  vec3 direction = pinholeDirection(vec2(pixel) + 0.5 + frame.rasterJitter);
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
  vec3 specular;
  vec3 color = shadeSurface(s, toEye / distance, distance * pixelAngle(), specular);
  float linearDepth = dot(s.position - frame.eye, frame.forward);
  imageStore(outColor, pixel, vec4(color, signedCoc(linearDepth)));
  imageStore(outSpecular, pixel, vec4(specular, 1.0));
  if (!firstSample) return;
  imageStore(outNormalDepth, pixel, vec4(normalize(s.normal), linearDepth));
  imageStore(outMotion, pixel, vec4(motionTo(vec4(s.position, 1.0), pixel), 0.0, 0.0));
}
