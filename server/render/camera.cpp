#include "render/camera.h"

#include <glm/gtc/matrix_transform.hpp>

namespace hdof {

Camera Camera::fromScene(const SceneCamera& sceneCamera) {
  Camera camera;
  camera.position = sceneCamera.position;
  camera.forward = glm::normalize(sceneCamera.forward);
  camera.up =
      glm::normalize(sceneCamera.up - camera.forward * glm::dot(sceneCamera.up, camera.forward));
  camera.znear = sceneCamera.znear;
  camera.zfar = sceneCamera.zfar;
  return camera;
}

namespace {
float aspectOf(uint32_t width, uint32_t height) {
  return static_cast<float>(width) / static_cast<float>(height);
}
}  // namespace

Lens withSceneCameraFov(Lens lens, const SceneCamera& sceneCamera, uint32_t width,
                        uint32_t height) {
  lens.focalLengthMm =
      focalLengthForVerticalFov(sceneCamera.yfov, lens.sensor, aspectOf(width, height));
  return lens;
}

glm::vec2 tanHalfFov(const Lens& lens, uint32_t width, uint32_t height) {
  return tanHalfFov(lens.focalLengthMm, lens.sensor, aspectOf(width, height));
}

glm::vec2 fieldOfViewDeg(const Lens& lens, uint32_t width, uint32_t height) {
  return glm::degrees(2.0f * glm::atan(tanHalfFov(lens, width, height)));
}

float focalLengthPixels(const Lens& lens, uint32_t width, uint32_t height) {
  return static_cast<float>(width) / (2.0f * tanHalfFov(lens, width, height).x);
}

gpu::FrameUniforms makeFrameUniforms(const Scene& scene, const Camera& camera, const Lens& lens,
                                     const FrameSettings& settings) {
  glm::vec2 tanHalf = tanHalfFov(lens, settings.width, settings.height);
  glm::vec3 right = glm::normalize(glm::cross(camera.forward, camera.up));
  glm::mat4 view = glm::lookAt(camera.position, camera.position + camera.forward, camera.up);
  glm::mat4 projection = glm::perspective(2.0f * std::atan(tanHalf.y),
                                          aspectOf(settings.width, settings.height),
                                          camera.znear, camera.zfar);
  projection[1][1] *= -1.0f;  // Vulkan's clip space has y pointing down

  gpu::FrameUniforms u{};
  u.viewProj = projection * view;
  u.previousViewProj = u.viewProj;
  u.eye = camera.position;
  u.tanHalfFovY = tanHalf.y;
  u.right = right;
  u.tanHalfFovX = tanHalf.x;
  u.up = camera.up;
  u.apertureDiameter = lens.apertureDiameter();
  u.forward = camera.forward;
  u.focusDistance = lens.focusDistance;
  u.focalLengthPixels = focalLengthPixels(lens, settings.width, settings.height);
  u.focalLength = lens.focalLengthMm * 0.001f;
  u.fNumber = lens.fNumber;
  u.acceptableCoc = acceptableCocMm(lens.sensor) * 0.001f;
  u.bladeCount = static_cast<float>(lens.blades);
  u.bladeRotation = lens.bladeRotation;
  u.skyColor = scene.skyColor;
  u.exposure = settings.exposure;
  u.groundColor = scene.groundColor;
  u.imageSize = glm::uvec2(settings.width, settings.height);
  u.frameIndex = settings.frameIndex;
  u.samplesPerPixel = settings.samplesPerPixel;
  u.lightCount = static_cast<uint32_t>(scene.lights.size());
  u.pixelJitter = settings.pixelJitter ? 1 : 0;
  u.znear = camera.znear;
  return u;
}

}  // namespace hdof
