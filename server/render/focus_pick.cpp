#include "render/focus_pick.h"

#include <cmath>

namespace hdof {

std::optional<SurfaceHit> surfaceUnderPixel(const Bvh& bvh, const Camera& camera, const Lens& lens,
                                            uint32_t width, uint32_t height, float x, float y) {
  // The ray through the pixel's centre, as the raster samples it (see makeFrameUniforms).
  glm::vec2 tanHalf = tanHalfFov(lens, width, height);
  float u = (std::floor(x) + 0.5f) / float(width) * 2.0f - 1.0f;
  float v = (std::floor(y) + 0.5f) / float(height) * 2.0f - 1.0f;
  glm::vec3 right = glm::normalize(glm::cross(camera.forward, camera.up));
  // forward has unit length and is orthogonal to the other two terms, so the hit's t is its
  // depth along forward.
  glm::vec3 direction = camera.forward + right * (u * tanHalf.x) - camera.up * (v * tanHalf.y);
  auto hit = intersect(bvh, camera.position, direction, camera.znear);
  if (!hit) return std::nullopt;
  glm::vec3 point = camera.position + direction * hit->t;
  return SurfaceHit{point, hit->t, glm::length(point - camera.position)};
}

std::optional<float> depthUnderPixel(const Bvh& bvh, const Camera& camera, const Lens& lens,
                                     uint32_t width, uint32_t height, float x, float y) {
  auto hit = surfaceUnderPixel(bvh, camera, lens, width, height, x, y);
  if (!hit) return std::nullopt;
  return hit->depth;
}

}  // namespace hdof
