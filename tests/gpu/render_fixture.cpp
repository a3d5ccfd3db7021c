#include "render_fixture.h"

#include "quality/occlusion_mask.h"

#include <gtest/gtest.h>

#include <glm/gtc/packing.hpp>
#include <stdexcept>

namespace hdof::test {

gpu::Context& testContext() {
  static gpu::Context context;
  return context;
}

SceneOnGpu& testScene(const std::string& spec) {
  testContext();  // constructed before the scenes, so destroyed after them
  static std::map<std::string, std::unique_ptr<SceneOnGpu>> scenes;
  auto& entry = scenes[spec];
  if (!entry) {
    entry = std::make_unique<SceneOnGpu>();
    entry->scene = loadScene(spec);
    entry->bvh = buildBvh(entry->scene.vertices, entry->scene.indices);
    entry->gpu = std::make_unique<GpuScene>(testContext(), entry->scene, entry->bvh);
  }
  return *entry;
}

Lens onSceneCameraSensor(Lens lens, const SceneCamera& camera, uint32_t width, uint32_t height) {
  float sensorHeight = 2.0f * lens.focalLengthMm * std::tan(0.5f * camera.yfov);
  lens.sensor = {sensorHeight * float(width) / float(height), sensorHeight};
  return lens;
}

FrameRequest requestFor(const RenderSpec& spec, const Scene& scene) {
  const SceneCamera* sceneCamera =
      spec.camera.empty() ? &scene.cameras.front() : scene.findCamera(spec.camera);
  EXPECT_NE(sceneCamera, nullptr) << spec.camera;
  FrameRequest request;
  request.mode = spec.mode;
  request.camera = Camera::fromScene(*sceneCamera);
  if (spec.znear > 0.0f) request.camera.znear = spec.znear;
  if (spec.eye && spec.target) {
    Camera& camera = request.camera;
    camera.position = *spec.eye;
    camera.forward = glm::normalize(*spec.target - *spec.eye);
    camera.up =
        glm::normalize(glm::vec3(0.0f, 1.0f, 0.0f) -
                       camera.forward * glm::dot(camera.forward, glm::vec3(0.0f, 1.0f, 0.0f)));
  }
  request.lens = onSceneCameraSensor(spec.lens, *sceneCamera, spec.width, spec.height);
  if (request.lens.focusDistance <= 0.0f)
    request.lens.focusDistance = sceneCamera->focusDistance.value_or(5.0f);
  request.settings.width = spec.width;
  request.settings.height = spec.height;
  request.settings.pixelJitter = spec.pixelJitter;
  request.traceEverywhere = spec.traceEverywhere;
  request.settings.samplesPerPixel = spec.raysPerPixel;
  return request;
}

ImageRgba8 renderImage(const RenderSpec& spec) {
  SceneOnGpu& scene = testScene(spec.scene);
  FrameRequest request = requestFor(spec, scene.scene);
  FramePipeline pipeline(testContext(), scene.scene, *scene.gpu, spec.width, spec.height);
  if (spec.mode == RenderMode::Reference) {
    pipeline.renderReference(request, spec.raysPerPixel);
  } else {
    for (uint32_t frame = 0; frame < spec.frames; ++frame) {
      request.settings.frameIndex = frame;
      pipeline.render(request);
    }
  }
  return pipeline.image();
}

ImageRgba8 renderImage(RenderSpec spec, RenderMode mode, uint32_t rays, uint32_t frames) {
  spec.mode = mode;
  spec.raysPerPixel = rays;
  spec.frames = frames;
  return renderImage(spec);
}

std::unique_ptr<FramePipeline> renderFirstFrame(const RenderSpec& spec) {
  SceneOnGpu& scene = testScene(spec.scene);
  auto pipeline = std::make_unique<FramePipeline>(testContext(), scene.scene, *scene.gpu,
                                                  spec.width, spec.height);
  pipeline->render(requestFor(spec, scene.scene));
  return pipeline;
}

std::vector<float> renderDepth(RenderSpec spec, FrameRequest* requestOut) {
  spec.mode = RenderMode::Pinhole;
  if (requestOut) *requestOut = requestFor(spec, testScene(spec.scene).scene);
  return renderFirstFrame(spec)->linearDepth();
}

void renderTruckOnto(FramePipeline& pipeline, FrameRequest request, int frames, float step) {
  Camera end = request.camera;
  glm::vec3 right = glm::normalize(glm::cross(end.forward, end.up));
  for (int left = frames - 1; left >= 0; --left) {
    request.camera.position = end.position - right * (step * float(left));
    pipeline.render(request);
  }
}

std::vector<uint8_t> occlusionRegion(const RenderSpec& spec) {
  FrameRequest request;
  std::vector<float> depth = renderDepth(spec, &request);
  return occlusionMask(depth, spec.width, spec.height,
                       cocParameters(request.lens, spec.width, spec.height));
}

std::vector<glm::vec4> readImage(const gpu::Image& image) {
  VkFormat format = image.desc().format;
  size_t texelBytes = format == VK_FORMAT_R16G16B16A16_SFLOAT ? 8
                      : format == VK_FORMAT_R16G16_SFLOAT     ? 4
                      : format == VK_FORMAT_R16_SFLOAT        ? 2
                      : format == VK_FORMAT_R8_UINT           ? 1
                      : format == VK_FORMAT_R32G32B32A32_SFLOAT
                          ? 16
                          : throw std::invalid_argument("readImage: unsupported format");
  size_t texels = size_t(image.width()) * image.height();
  gpu::Buffer buffer(testContext(), texels * texelBytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                     gpu::MemoryUse::Readback, "test readback");
  testContext().submitAndWait(
      [&](VkCommandBuffer cmd) { gpu::copyImageToBuffer(cmd, image, buffer); });
  std::vector<glm::vec4> out(texels);
  const auto* words = static_cast<const uint32_t*>(buffer.mapped());
  for (size_t i = 0; i < texels; ++i) {
    if (texelBytes == 8)
      out[i] = glm::vec4(glm::unpackHalf2x16(words[2 * i]), glm::unpackHalf2x16(words[2 * i + 1]));
    else if (texelBytes == 4)
      out[i] = glm::vec4(glm::unpackHalf2x16(words[i]), 0.0f, 0.0f);
    else if (texelBytes == 2)
      out[i] = glm::vec4(glm::unpackHalf2x16(static_cast<const uint16_t*>(buffer.mapped())[i]).x,
                         0.0f, 0.0f, 0.0f);
    else if (texelBytes == 1)
      out[i] = glm::vec4(float(static_cast<const uint8_t*>(buffer.mapped())[i]), 0.0f, 0.0f, 0.0f);
    else
      out[i] = static_cast<const glm::vec4*>(buffer.mapped())[i];
  }
  return out;
}

double meanSquaredError(const ImageRgba8& a, const ImageRgba8& b) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    if (i % 4 == 3) continue;
    double d = double(a.pixels[i]) - double(b.pixels[i]);
    sum += d * d;
    ++count;
  }
  return sum / double(count);
}

}  // namespace hdof::test
