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
  u.eye = glm::vec4(camera.position, tanHalfY);
  u.right = glm::vec4(right, tanHalfY * aspect);
  u.up = glm::vec4(camera.up, lens.apertureDiameter());
  u.forward = glm::vec4(camera.forward, lens.focusDistance);
  u.lens = glm::vec4(focalLengthPixels(camera, settings.width, settings.height),
                     lens.focalLengthMm * 0.001f, lens.fNumber, static_cast<float>(lens.blades));
  u.lensShape = glm::vec4(lens.bladeRotation, 0.0f, 0.0f, 0.0f);
  u.skyColor = glm::vec4(scene.skyColor, settings.exposure);
  u.groundColor = glm::vec4(scene.groundColor, 0.0f);
  u.image =
      glm::uvec4(settings.width, settings.height, settings.frameIndex, settings.samplesPerPixel);
  u.options =
      glm::uvec4(static_cast<uint32_t>(scene.lights.size()), settings.pixelJitter ? 1 : 0, 0, 0);
  return u;
}

}  // namespace hdof
