// Motion vectors of the G-buffer: where each pixel's surface was in the previous frame.
#include "render_fixture.h"

#include <gtest/gtest.h>

namespace hdof::test {
namespace {

TEST(MotionVectors, FollowTheCameraAndVanishAfterACut) {
  SceneOnGpu& scene = testScene("builtin:wall");  // a wall square-on at 3 m
  const uint32_t width = 160, height = 90;
  FramePipeline pipeline(testContext(), scene.scene, *scene.gpu, width, height);
  FrameRequest request;
  request.camera = Camera::fromScene(scene.scene.cameras.front());
  request.lens = onSceneCameraSensor(request.lens, scene.scene.cameras.front(), width, height);
  request.settings.width = width;
  request.settings.height = height;

  auto expectStill = [&](const char* when) {
    for (glm::vec2 m : pipeline.motionVectors()) ASSERT_LT(glm::length(m), 1e-3f) << when;
  };
  pipeline.render(request);
  expectStill("first frame");

  // The camera moves 10 cm to its right: the wall's points were further right on screen.
  const float step = 0.1f, distance = 3.0f;
  request.camera.position +=
      step * glm::normalize(glm::cross(request.camera.forward, request.camera.up));
  pipeline.render(request);
  std::vector<glm::vec2> motion = pipeline.motionVectors();
  float expected = focalLengthPixels(request.lens, width, height) * step / distance;
  for (uint32_t y = 10; y < height; y += 20)
    for (uint32_t x = 10; x < width; x += 20) {
      glm::vec2 m = motion[y * width + x];
      EXPECT_NEAR(m.x, expected, 0.02f * expected + 0.01f) << x << "," << y;
      EXPECT_NEAR(m.y, 0.0f, 0.02f) << x << "," << y;
    }

  pipeline.cut();
  pipeline.render(request);
  expectStill("after a cut");
}

}  // namespace
}  // namespace hdof::test
