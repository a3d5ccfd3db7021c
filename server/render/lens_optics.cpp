#include "render/lens_optics.h"

#include <cmath>
#include <limits>

namespace hdof {
namespace {

struct NamedSensor {
  const char* name;
  Sensor sensor;
};
constexpr NamedSensor kPresets[] = {{"full-frame", {36.0f, 24.0f}},
                                    {"super35", {24.89f, 18.66f}},
                                    {"aps-c", {23.6f, 15.6f}},
                                    {"aps-c-canon", {22.3f, 14.9f}},
                                    {"mft", {17.3f, 13.0f}}};

}  // namespace

std::optional<Sensor> sensorPreset(const std::string& name) {
  for (const NamedSensor& preset : kPresets)
    if (name == preset.name) return preset.sensor;
  return std::nullopt;
}

std::string sensorPresetNames() {
  std::string names;
  for (const NamedSensor& preset : kPresets) names += (names.empty() ? "" : ", ") + std::string(preset.name);
  return names;
}

glm::vec2 imageExtentMm(const Sensor& sensor, float aspect) {
  if (aspect >= sensor.widthMm / sensor.heightMm) return {sensor.widthMm, sensor.widthMm / aspect};
  return {sensor.heightMm * aspect, sensor.heightMm};
}

glm::vec2 tanHalfFov(float focalLengthMm, const Sensor& sensor, float aspect) {
  return imageExtentMm(sensor, aspect) / (2.0f * focalLengthMm);
}

float focalLengthForVerticalFov(float yfov, const Sensor& sensor, float aspect) {
  return imageExtentMm(sensor, aspect).y / (2.0f * std::tan(0.5f * yfov));
}

float acceptableCocMm(const Sensor& sensor) {
  return std::hypot(sensor.widthMm, sensor.heightMm) / 1500.0f;
}

DepthOfField depthOfField(float focalLengthMm, float fNumber, float focusDistance, float cocMm) {
  // In metres throughout.
  float f = focalLengthMm * 0.001f, c = cocMm * 0.001f, s = focusDistance;
  DepthOfField dof;
  dof.hyperfocal = f * f / (fNumber * c) + f;
  float h = dof.hyperfocal;
  dof.near = s * (h - f) / (h + s - 2.0f * f);
  dof.far = s < h ? s * (h - f) / (h - s) : std::numeric_limits<float>::infinity();
  return dof;
}

}  // namespace hdof
