// The camera and the thin lens the user controls, and the per-frame uniforms made from them.
#pragma once

#include "render/lens_optics.h"
#include "scene/scene.h"

#include <shared/frame.h>

namespace hdof {

// Where the camera stands and looks. Its field of view is the lens's (focal length and sensor).
struct Camera {
  glm::vec3 position{0.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};  // unit
  glm::vec3 up{0.0f, 1.0f, 0.0f};        // unit, orthogonal to forward
  float znear = 0.05f, zfar = 1000.0f;

  static Camera fromScene(const SceneCamera& sceneCamera);
  bool operator==(const Camera&) const = default;
};

// Thin lens on a sensor: the aperture diameter is focal length / f-number, and focal length and
// sensor make the field of view (render/lens_optics.h); see shared/frame.h for how the circle of
// confusion follows.
struct Lens {
  float focalLengthMm = 50.0f;
  float fNumber = 2.8f;        // >= 0.5; very large numbers make a pinhole
  float focusDistance = 5.0f;  // metres, > 0
  uint32_t blades = 0;         // aperture blades; 0 for a circular aperture
  float bladeRotation = 0.0f;  // radians
  Sensor sensor;

  float apertureDiameter() const { return focalLengthMm * 0.001f / fNumber; }
  bool operator==(const Lens&) const = default;
};

// The lens that frames an image of this size as the scene camera does (its vertical field of
// view on the lens's sensor); everything else stays the given lens's.
Lens withSceneCameraFov(Lens lens, const SceneCamera& sceneCamera, uint32_t width,
                        uint32_t height);

struct FrameSettings {
  uint32_t width = 640, height = 360;
  uint32_t frameIndex = 0;
  uint32_t samplesPerPixel = 1;
  bool pixelJitter = true;
  float exposure = 1.0f;
};

gpu::FrameUniforms makeFrameUniforms(const Scene& scene, const Camera& camera, const Lens& lens,
                                     const FrameSettings& settings);

// tan of half the lens's horizontal (x) and vertical (y) field of view at this image size.
glm::vec2 tanHalfFov(const Lens& lens, uint32_t width, uint32_t height);
// The horizontal (x) and vertical (y) field of view in degrees, as messages and reports give it.
glm::vec2 fieldOfViewDeg(const Lens& lens, uint32_t width, uint32_t height);
// Focal length in pixels at this image size (width / (2 tan(hfov/2))).
float focalLengthPixels(const Lens& lens, uint32_t width, uint32_t height);

}  // namespace hdof
