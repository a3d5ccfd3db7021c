// The camera and the thin lens the user controls, and the per-frame uniforms made from them.
#pragma once

#include "scene/scene.h"

#include <shared/frame.h>

namespace hdof {

struct Camera {
  glm::vec3 position{0.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};  // unit
  glm::vec3 up{0.0f, 1.0f, 0.0f};        // unit, orthogonal to forward
  float yfov = 0.7f;                     // vertical field of view, radians
  float znear = 0.05f, zfar = 1000.0f;

  static Camera fromScene(const SceneCamera& sceneCamera);
};

// Thin lens: the aperture diameter is focal length / f-number; the field of view stays the
// camera's (see shared/frame.h for how the circle of confusion follows from both).
struct Lens {
  float focalLengthMm = 50.0f;
  float fNumber = 2.8f;        // >= 0.5; very large numbers make a pinhole
  float focusDistance = 5.0f;  // metres, > 0
  uint32_t blades = 0;         // aperture blades; 0 for a circular aperture
  float bladeRotation = 0.0f;  // radians

  float apertureDiameter() const { return focalLengthMm * 0.001f / fNumber; }
};

struct FrameSettings {
  uint32_t width = 640, height = 360;
  uint32_t frameIndex = 0;
  uint32_t samplesPerPixel = 1;
  bool pixelJitter = true;
  float exposure = 1.0f;
};

gpu::FrameUniforms makeFrameUniforms(const Scene& scene, const Camera& camera, const Lens& lens,
                                     const FrameSettings& settings);

// Focal length in pixels for the camera at this image size (width / (2 tan(hfov/2))).
float focalLengthPixels(const Camera& camera, uint32_t width, uint32_t height);

}  // namespace hdof
