// Focus picking: the depth of the surface under a pixel, from the scene's BVH on the CPU (one
// ray, any render mode, no GPU round trip).
#pragma once

#include "render/camera.h"
#include "scene/bvh.h"

#include <optional>

namespace hdof {

// The closest surface through the centre of a pixel: where it is, how far along the camera's
// forward axis (its view depth) and along the ray.
struct SurfaceHit {
  glm::vec3 point{0.0f};
  float depth = 0.0f, distance = 0.0f;
};
std::optional<SurfaceHit> surfaceUnderPixel(const Bvh& bvh, const Camera& camera, const Lens& lens,
                                            uint32_t width, uint32_t height, float x, float y);

// The view depth (metres along the camera's forward axis, as the thin lens's focus distance is
// measured) of the closest surface through the centre of pixel (x, y) of a width x height image,
// or nothing where the ray meets no surface.
std::optional<float> depthUnderPixel(const Bvh& bvh, const Camera& camera, const Lens& lens,
                                     uint32_t width, uint32_t height, float x, float y);

}  // namespace hdof
