// The lens maths against values worked out by hand: field of view from focal length and sensor
// (and the reverse), the acceptable circle of confusion, hyperfocal distance and the near and far
// limits of acceptable sharpness.
#include "render/camera.h"
#include "render/lens_optics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hdof {
namespace {

float degrees(float radians) { return radians * 180.0f / float(M_PI); }

TEST(LensOptics, FieldOfViewFromFocalLengthAndSensor) {
  Sensor fullFrame;
  // An image of the sensor's own aspect (3:2) uses all of it: 50 mm sees 2 atan(18/50) = 39.598
  // degrees across and 2 atan(12/50) = 26.991 degrees up.
  glm::vec2 t = tanHalfFov(50.0f, fullFrame, 1.5f);
  EXPECT_NEAR(degrees(2.0f * std::atan(t.x)), 39.598f, 0.001f);
  EXPECT_NEAR(degrees(2.0f * std::atan(t.y)), 26.991f, 0.001f);
  // Wider (16:9): the full width, 36 x 20.25 mm: 2 atan(10.125/50) = 22.895 degrees up.
  EXPECT_EQ(imageExtentMm(fullFrame, 16.0f / 9.0f), glm::vec2(36.0f, 20.25f));
  EXPECT_NEAR(degrees(2.0f * std::atan(tanHalfFov(50.0f, fullFrame, 16.0f / 9.0f).y)), 22.895f,
              0.001f);
  // Narrower (4:3): the full height, 32 x 24 mm: 2 atan(16/50) = 35.489 degrees across.
  EXPECT_NEAR(imageExtentMm(fullFrame, 4.0f / 3.0f).x, 32.0f, 1e-4f);
  EXPECT_NEAR(degrees(2.0f * std::atan(tanHalfFov(50.0f, fullFrame, 4.0f / 3.0f).x)), 35.489f,
              0.001f);
  // Portrait 9:16 on a landscape sensor: 13.5 x 24 mm.
  EXPECT_NEAR(imageExtentMm(fullFrame, 9.0f / 16.0f).x, 13.5f, 1e-4f);
  // A longer lens zooms in: twice the focal length, half the tangent.
  EXPECT_NEAR(tanHalfFov(100.0f, fullFrame, 1.5f).x, 0.5f * t.x, 1e-6f);
  // Micro Four Thirds at 16:9: 17.3 mm across.
  EXPECT_NEAR(imageExtentMm(*sensorPreset("mft"), 16.0f / 9.0f).y, 9.73125f, 1e-4f);
}

TEST(LensOptics, FocalLengthKeepsAFieldOfView) {
  // 40 degrees up at 16:9 on full frame: 20.25 / (2 tan 20 degrees) = 27.818 mm.
  EXPECT_NEAR(focalLengthForVerticalFov(glm::radians(40.0f), Sensor{}, 16.0f / 9.0f), 27.818f,
              0.001f);
  // The closeup's old framing and blur: 50 mm on a 64.7 x 36.4 mm sensor sees 40 degrees up.
  EXPECT_NEAR(focalLengthForVerticalFov(0.698f, Sensor{64.7f, 36.4f}, 16.0f / 9.0f), 50.0f, 0.05f);
  // The round trip through a scene camera at any aspect.
  SceneCamera closeup;
  closeup.yfov = 0.698f;
  for (auto [width, height] : {std::pair{1280u, 720u}, {800u, 800u}, {400u, 900u}}) {
    Lens lens = withSceneCameraFov(Lens{}, closeup, width, height);
    EXPECT_NEAR(2.0f * std::atan(tanHalfFov(lens, width, height).y), 0.698f, 1e-5f);
    EXPECT_NEAR(fieldOfViewDeg(lens, width, height).y, degrees(0.698f), 1e-3f);
  }
}

TEST(LensOptics, SensorPresets) {
  EXPECT_EQ(*sensorPreset("full-frame"), (Sensor{36.0f, 24.0f}));
  EXPECT_EQ(*sensorPreset("super35"), (Sensor{24.89f, 18.66f}));
  EXPECT_EQ(*sensorPreset("aps-c"), (Sensor{23.6f, 15.6f}));
  EXPECT_EQ(*sensorPreset("aps-c-canon"), (Sensor{22.3f, 14.9f}));
  EXPECT_EQ(*sensorPreset("mft"), (Sensor{17.3f, 13.0f}));
  EXPECT_FALSE(sensorPreset("medium-format"));
  EXPECT_EQ(sensorPresetNames(), "full-frame, super35, aps-c, aps-c-canon, mft");
}

TEST(LensOptics, AcceptableCircleOfConfusionIsTheDiagonalOver1500) {
  // sqrt(36^2 + 24^2) = 43.267 mm; / 1500 = 0.028844 mm. MFT: 21.640 / 1500 = 0.014427 mm.
  EXPECT_NEAR(acceptableCocMm(Sensor{}), 0.028844f, 1e-6f);
  EXPECT_NEAR(acceptableCocMm(*sensorPreset("mft")), 0.014427f, 1e-6f);
}

TEST(LensOptics, HyperfocalNearAndFarLimits) {
  // 50 mm at f/1.4, c = 0.03 mm, focused at 2.4 m: H = 0.05^2 / (1.4 * 0.00003) + 0.05 =
  // 59.5738 m; near = 2.4 * 59.5238 / (59.5738 + 2.4 - 0.1) = 2.30885 m; far = 2.4 * 59.5238 /
  // (59.5738 - 2.4) = 2.49865 m.
  DepthOfField dof = depthOfField(50.0f, 1.4f, 2.4f, 0.03f);
  EXPECT_NEAR(dof.hyperfocal, 59.5738f, 1e-3f);
  EXPECT_NEAR(dof.near, 2.30885f, 1e-4f);
  EXPECT_NEAR(dof.far, 2.49865f, 1e-4f);
  // 35 mm at f/8, c = 0.03 mm: H = 5.13917 m. Focused there: sharp from H/2 to infinity.
  DepthOfField atHyperfocal = depthOfField(35.0f, 8.0f, 5.139167f, 0.03f);
  EXPECT_NEAR(atHyperfocal.hyperfocal, 5.13917f, 1e-4f);
  EXPECT_NEAR(atHyperfocal.near, 2.56958f, 1e-4f);
  EXPECT_TRUE(std::isinf(atHyperfocal.far));
  // Beyond it (10 m): near = 10 * 5.10417 / (5.13917 + 10 - 0.07) = 3.38716 m, far infinite.
  DepthOfField beyond = depthOfField(35.0f, 8.0f, 10.0f, 0.03f);
  EXPECT_NEAR(beyond.near, 3.38716f, 1e-4f);
  EXPECT_TRUE(std::isinf(beyond.far));
}

}  // namespace
}  // namespace hdof
