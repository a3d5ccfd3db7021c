#include "render/camera.h"

#include <glm/gtc/matrix_transform.hpp>

namespace hdof {

Camera Camera::fromScene(const SceneCamera& sceneCamera) {
  Camera camera;
  camera.position = sceneCamera.position;
  camera.forward = glm::normalize(sceneCamera.forward);
  camera.up =
      glm::normalize(sceneCamera.up - camera.forward * glm::dot(sceneCamera.up, camera.forward));
  camera.yfov = sceneCamera.yfov;
  camera.znear = sceneCamera.znear;
  camera.zfar = sceneCamera.zfar;
  return camera;
}

float focalLengthPixels(const Camera& camera, uint32_t width, uint32_t height) {
  float tanHalfY = std::tan(camera.yfov * 0.5f);
  float tanHalfX = tanHalfY * static_cast<float>(width) / static_cast<float>(height);
  return static_cast<float>(width) / (2.0f * tanHalfX);
}

gpu::FrameUniforms makeFrameUniforms(const Scene& scene, const Camera& camera, const Lens& lens,
                                     const FrameSettings& settings) {
  float aspect = static_cast<float>(settings.width) / static_cast<float>(settings.height);
  float tanHalfY = std::tan(camera.yfov * 0.5f);
  glm::vec3 right = glm::normalize(glm::cross(camera.forward, camera.up));
  glm::mat4 view = glm::lookAt(camera.position, camera.position + camera.forward, camera.up);
  glm::mat4 projection = glm::perspective(camera.yfov, aspect, camera.znear, camera.zfar);
  projection[1][1] *= -1.0f;  // Vulkan's clip space has y pointing down

  gpu::FrameUniforms u{};
  u.viewProj = projection * view;
  u.previousViewProj = u.viewProj;
  u.eye = camera.position;
  u.tanHalfFovY = tanHalfY;
  u.right = right;
  u.tanHalfFovX = tanHalfY * aspect;
  u.up = camera.up;
  u.apertureDiameter = lens.apertureDiameter();
  u.forward = camera.forward;
  u.focusDistance = lens.focusDistance;
  u.focalLengthPixels = focalLengthPixels(camera, settings.width, settings.height);
  u.focalLength = lens.focalLengthMm * 0.001f;
  u.fNumber = lens.fNumber;
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
  return u;
}

}  // namespace hdof
