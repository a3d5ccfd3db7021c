// A physical lens on a stated sensor: the field of view a focal length gives, the focal length
// that gives a field of view, and what a camera assistant reads (hyperfocal distance, near and far
// limits of acceptable sharpness). client_web/optics.js is the browser's copy of these formulas.
//
// How the sensor maps onto an image whose aspect differs from the sensor's: the image is the
// largest rectangle of its aspect centred on the sensor, as a camera records 16:9 video from a 3:2
// sensor. An image wider than the sensor uses the sensor's full width (and less of its height); a
// narrower one its full height. The field of view is that of the lens focused at infinity
// (tan(fov/2) = extent / 2f): focusing does not change the framing.
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <string>

namespace hdof {

struct Sensor {
  float widthMm = 36.0f, heightMm = 24.0f;  // full frame
  bool operator==(const Sensor&) const = default;
};
// Each side, from a phone's sensor to large format (in the CLI and the protocol alike).
constexpr float kMinSensorMm = 1.0f, kMaxSensorMm = 300.0f;

// The named sensors: full-frame 36x24, super35 24.89x18.66, aps-c 23.6x15.6, aps-c-canon
// 22.3x14.9, mft 17.3x13.
std::optional<Sensor> sensorPreset(const std::string& name);
std::string sensorPresetNames();  // "full-frame, super35, ..."

// The part of the sensor (mm) an image of this aspect (width / height) takes.
glm::vec2 imageExtentMm(const Sensor& sensor, float aspect);
// tan of half the horizontal (x) and vertical (y) field of view.
glm::vec2 tanHalfFov(float focalLengthMm, const Sensor& sensor, float aspect);
// The focal length whose vertical field of view on this sensor and aspect is yfov (radians).
float focalLengthForVerticalFov(float yfov, const Sensor& sensor, float aspect);

// The circle of confusion accepted as sharp: the sensor's diagonal / 1500 (0.0288 mm on full
// frame), the usual criterion for a print viewed at its diagonal.
float acceptableCocMm(const Sensor& sensor);

struct DepthOfField {
  float hyperfocal = 0.0f;  // metres
  float near = 0.0f;        // metres
  float far = 0.0f;         // metres; infinity when focused at or beyond the hyperfocal distance
};
// Thin lens: H = f^2 / (N c) + f, near = s (H - f) / (H + s - 2f), far = s (H - f) / (H - s).
DepthOfField depthOfField(float focalLengthMm, float fNumber, float focusDistance, float cocMm);

}  // namespace hdof
