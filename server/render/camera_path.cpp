#include "render/camera_path.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace hdof {
namespace {

using nlohmann::json;

glm::vec3 readVec3(const json& object, const char* key, size_t index) {
  const json& value = object.at(key);
  if (!value.is_array() || value.size() != 3)
    throw std::invalid_argument("keyframe " + std::to_string(index) + ": '" + key +
                                "' must be an array of 3 numbers");
  glm::vec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!value[i].is_number())
      throw std::invalid_argument("keyframe " + std::to_string(index) + ": '" + key +
                                  "' must be an array of 3 numbers");
    v[i] = value[i].get<float>();
    if (!std::isfinite(v[i]))
      throw std::invalid_argument("keyframe " + std::to_string(index) + ": '" + key +
                                  "' is not finite");
  }
  return v;
}

std::optional<float> readPositive(const json& object, const char* key, size_t index, float lo,
                                  float hi) {
  if (!object.contains(key)) return std::nullopt;
  const json& value = object[key];
  if (!value.is_number() || !(value.get<double>() >= lo && value.get<double>() <= hi))
    throw std::invalid_argument("keyframe " + std::to_string(index) + ": '" + key +
                                "' must be a number from " + std::to_string(lo) + " to " +
                                std::to_string(hi));
  return value.get<float>();
}

// Catmull-Rom between p1 and p2, written as p1 plus the neighbours' offsets from it: where the
// keyframes are alike (a camera held still) the offsets are exactly zero and so is the motion
// (the sum of the four points' weights rounds differently from frame to frame, and the renderers
// take any change of the view for motion).
glm::vec3 catmullRom(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
                     const glm::vec3& p3, float t) {
  glm::vec3 d0 = p0 - p1, d2 = p2 - p1, d3 = p3 - p1;
  return p1 +
         0.5f * t * ((d2 - d0) + t * ((2.0f * d0 + 4.0f * d2 - d3) + t * (d3 - d0 - 3.0f * d2)));
}

// Linear interpolation of an optional lens field between the keyframes around `time`.
std::optional<float> lerpField(const std::vector<CameraKeyframe>& keys, size_t segment, float t,
                               std::optional<float> CameraKeyframe::*field) {
  const auto& a = keys[segment].*field;
  const auto& b = keys[std::min(segment + 1, keys.size() - 1)].*field;
  if (a && b) return *a + (*b - *a) * t;
  return a ? a : b;
}

}  // namespace

CameraPath CameraPath::parse(const std::string& text) {
  json document;
  try {
    document = json::parse(text);
  } catch (const json::parse_error& e) {
    std::string what = e.what();
    throw std::invalid_argument("not valid JSON (" + what.substr(what.find(']') + 2) + ")");
  }
  if (!document.is_object() || !document.contains("keyframes") ||
      !document["keyframes"].is_array() || document["keyframes"].empty())
    throw std::invalid_argument("expected {\"keyframes\": [...]} with at least one keyframe");
  CameraPath path;
  const json& keys = document["keyframes"];
  bool timed = keys[0].is_object() && keys[0].contains("time");
  for (size_t i = 0; i < keys.size(); ++i) {
    const json& k = keys[i];
    if (!k.is_object() || !k.contains("position") || !k.contains("target"))
      throw std::invalid_argument("keyframe " + std::to_string(i) +
                                  " needs \"position\" and \"target\"");
    CameraKeyframe key;
    key.position = readVec3(k, "position", i);
    key.target = readVec3(k, "target", i);
    if (k.contains("up")) key.up = readVec3(k, "up", i);
    if (glm::length(key.target - key.position) < 1e-6f)
      throw std::invalid_argument("keyframe " + std::to_string(i) + ": target equals position");
    if (timed) {
      if (!k.contains("time") || !k["time"].is_number())
        throw std::invalid_argument("keyframe " + std::to_string(i) +
                                    ": \"time\" must be given on every keyframe or none");
      key.time = k["time"].get<float>();
      if (!std::isfinite(key.time) || (i > 0 && key.time <= path.keyframes_.back().time))
        throw std::invalid_argument("keyframe " + std::to_string(i) +
                                    ": times must be finite and increase");
    } else {
      key.time = keys.size() > 1 ? float(i) / float(keys.size() - 1) : 0.0f;
    }
    // A path written when the field of view was the camera's would silently lose its zoom.
    if (k.contains("yfov_deg"))
      throw std::invalid_argument("keyframe " + std::to_string(i) +
                                  ": 'yfov_deg' is no longer read: the field of view follows the "
                                  "lens, so give 'focal_length_mm' (on the --sensor) instead");
    key.focalLengthMm = readPositive(k, "focal_length_mm", i, 1.0f, 5000.0f);
    key.fNumber = readPositive(k, "f_number", i, 0.5f, 1e7f);
    key.focusDistance = readPositive(k, "focus_distance", i, 0.01f, 1e5f);
    path.keyframes_.push_back(key);
  }
  return path;
}

CameraPath CameraPath::load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("cannot read camera path '" + path + "'");
  std::stringstream text;
  text << in.rdbuf();
  try {
    return parse(text.str());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("camera path '" + path + "': " + e.what());
  }
}

void CameraPath::sample(float fraction, const Camera& baseCamera, const Lens& baseLens,
                        Camera& camera, Lens& lens) const {
  const auto& keys = keyframes_;
  float time =
      keys.front().time + std::clamp(fraction, 0.0f, 1.0f) * (keys.back().time - keys.front().time);
  size_t segment = 0;
  while (segment + 2 < keys.size() && keys[segment + 1].time <= time) ++segment;
  size_t next = std::min(segment + 1, keys.size() - 1);
  float span = keys[next].time - keys[segment].time;
  float t = span > 0.0f ? std::clamp((time - keys[segment].time) / span, 0.0f, 1.0f) : 0.0f;
  const CameraKeyframe& k0 = keys[segment == 0 ? 0 : segment - 1];
  const CameraKeyframe& k1 = keys[segment];
  const CameraKeyframe& k2 = keys[next];
  const CameraKeyframe& k3 = keys[std::min(next + 1, keys.size() - 1)];

  camera = baseCamera;
  camera.position = catmullRom(k0.position, k1.position, k2.position, k3.position, t);
  glm::vec3 target = catmullRom(k0.target, k1.target, k2.target, k3.target, t);
  camera.forward = glm::normalize(target - camera.position);
  glm::vec3 up = glm::normalize(k1.up + (k2.up - k1.up) * t);  // exact where they are alike
  glm::vec3 right = glm::cross(camera.forward, up);
  if (glm::length(right) < 1e-6f) right = glm::cross(camera.forward, glm::vec3(1.0f, 0.0f, 0.0f));
  camera.up = glm::normalize(glm::cross(glm::normalize(right), camera.forward));

  lens = baseLens;
  if (auto v = lerpField(keys, segment, t, &CameraKeyframe::focalLengthMm)) lens.focalLengthMm = *v;
  if (auto v = lerpField(keys, segment, t, &CameraKeyframe::fNumber)) lens.fNumber = *v;
  if (auto v = lerpField(keys, segment, t, &CameraKeyframe::focusDistance)) lens.focusDistance = *v;
}

}  // namespace hdof
