// Camera paths: parsing (with clear errors) and interpolation.
#include "render/camera_path.h"

#include <gtest/gtest.h>

namespace hdof {
namespace {

const char* kTwoKeys = R"({"keyframes": [
  {"position": [0, 1, 0], "target": [0, 1, -5], "f_number": 2.0, "focus_distance": 2.0},
  {"position": [2, 1, 0], "target": [2, 1, -5], "f_number": 4.0, "focus_distance": 4.0}]})";

TEST(CameraPath, InterpolatesPositionAndLens) {
  CameraPath path = CameraPath::parse(kTwoKeys);
  ASSERT_EQ(path.keyframes().size(), 2u);
  Camera base, camera;
  Lens baseLens, lens;
  baseLens.focalLengthMm = 35.0f;
  path.sample(0.0f, base, baseLens, camera, lens);
  EXPECT_NEAR(camera.position.x, 0.0f, 1e-6f);
  EXPECT_NEAR(lens.fNumber, 2.0f, 1e-6f);
  path.sample(0.5f, base, baseLens, camera, lens);
  EXPECT_NEAR(camera.position.x, 1.0f, 1e-5f);
  EXPECT_NEAR(lens.focusDistance, 3.0f, 1e-5f);
  EXPECT_NEAR(lens.focalLengthMm, 35.0f, 1e-6f);  // not in the path: the caller's
  EXPECT_NEAR(glm::length(camera.forward), 1.0f, 1e-5f);
  EXPECT_NEAR(glm::dot(camera.forward, camera.up), 0.0f, 1e-5f);
  path.sample(1.0f, base, baseLens, camera, lens);
  EXPECT_NEAR(camera.position.x, 2.0f, 1e-5f);
  EXPECT_NEAR(camera.forward.z, -1.0f, 1e-5f);
}

TEST(CameraPath, PassesThroughEveryKeyframe) {
  CameraPath path = CameraPath::parse(R"({"keyframes": [
    {"time": 0, "position": [0, 0, 0], "target": [0, 0, -1]},
    {"time": 1, "position": [1, 2, 0], "target": [0, 0, -1]},
    {"time": 3, "position": [4, 0, 1], "target": [0, 0, -1]}]})");
  Camera camera;
  Lens lens;
  path.sample(1.0f / 3.0f, Camera{}, Lens{}, camera, lens);  // time 1
  EXPECT_NEAR(camera.position.y, 2.0f, 1e-5f);
  path.sample(1.0f, Camera{}, Lens{}, camera, lens);
  EXPECT_NEAR(camera.position.x, 4.0f, 1e-5f);
}

// A path that holds the camera still (its keyframes alike) gives the same camera bit for bit at
// every frame: the renderers take any change, however small, for motion and restart their
// accumulation.
TEST(CameraPath, AStillPathGivesTheSameCameraAtEveryFrame) {
  CameraPath path = CameraPath::parse(R"({"keyframes": [
    {"position": [4.0, 1.0, -3.5], "target": [1.5, 0.8, -1.0], "up": [0.1, 0.9, 0.3],
     "focus_distance": 3.7},
    {"position": [4.0, 1.0, -3.5], "target": [1.5, 0.8, -1.0], "up": [0.1, 0.9, 0.3],
     "focus_distance": 3.7}]})");
  Camera first, camera;
  Lens firstLens, lens;
  path.sample(0.0f, Camera{}, Lens{}, first, firstLens);
  for (int frame = 1; frame < 32; ++frame) {
    path.sample(float(frame) / 31.0f, Camera{}, Lens{}, camera, lens);
    EXPECT_EQ(camera.position, first.position) << "frame " << frame;
    EXPECT_EQ(camera.forward, first.forward) << "frame " << frame;
    EXPECT_EQ(camera.up, first.up) << "frame " << frame;
    EXPECT_EQ(lens.focusDistance, firstLens.focusDistance) << "frame " << frame;
  }
}

TEST(CameraPath, RejectsBadInputWithAReason) {
  for (const char* bad : {"", "[]", "{\"keyframes\": []}", "{\"keyframes\": [{}]}",
                          R"({"keyframes": [{"position": [0, 0], "target": [0, 0, 1]}]})",
                          R"({"keyframes": [{"position": [0, 0, 0], "target": [0, 0, 0]}]})",
                          R"({"keyframes": [{"position": [0, 0, 0], "target": [0, 0, 1],
                              "f_number": -1}]})",
                          R"({"keyframes": [{"time": 1, "position": [0, 0, 0], "target": [0, 0, 1]},
                              {"time": 0, "position": [0, 0, 0], "target": [0, 0, 1]}]})",
                          R"({"keyframes": [{"position": ["a", 0, 0], "target": [0, 0, 1]}]})"}) {
    EXPECT_THROW(CameraPath::parse(bad), std::invalid_argument) << bad;
  }
  EXPECT_THROW(CameraPath::load("/no/such/path.json"), std::invalid_argument);
}

}  // namespace
}  // namespace hdof
