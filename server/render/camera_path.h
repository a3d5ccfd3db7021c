// Camera paths for sequences: keyframes of position, target and lens, read from JSON and
// interpolated (Catmull-Rom for the view, linear for the lens).
//
// {"keyframes": [{"time": 0.0, "position": [x, y, z], "target": [x, y, z], "up": [0, 1, 0],
//                 "focal_length_mm": 50, "f_number": 1.4, "focus_distance": 2.4},
//                ...]}
// Only position and target are required. Times, when given, must increase; without them the
// keyframes are spread evenly. Lens fields missing from every keyframe keep the caller's lens;
// the focal length, on the caller's sensor, is also the field of view (a zoom).
#pragma once

#include "render/camera.h"

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace hdof {

struct CameraKeyframe {
  float time = 0.0f;
  glm::vec3 position{0.0f}, target{0.0f, 0.0f, -1.0f}, up{0.0f, 1.0f, 0.0f};
  std::optional<float> focalLengthMm, fNumber, focusDistance;
};

class CameraPath {
 public:
  // Throws std::invalid_argument with a one-line reason on malformed input.
  static CameraPath parse(const std::string& json);
  static CameraPath load(const std::string& path);

  // The view and lens at `fraction` (0 = first keyframe, 1 = last); fields the path does not set
  // come from baseCamera / baseLens.
  void sample(float fraction, const Camera& baseCamera, const Lens& baseLens, Camera& camera,
              Lens& lens) const;
  const std::vector<CameraKeyframe>& keyframes() const { return keyframes_; }

 private:
  std::vector<CameraKeyframe> keyframes_;
};

}  // namespace hdof
