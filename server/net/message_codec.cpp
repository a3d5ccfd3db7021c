#include "net/message_codec.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <initializer_list>

namespace hdof::net {
namespace {

using nlohmann::json;

// Thrown by the checks below and caught by parseClientMessage: the first problem found wins.
struct Rejected {
  ProtocolError error;
};

[[noreturn]] void reject(ErrorCode code, const std::string& field, const std::string& message) {
  throw Rejected{{code, message, field}};
}

std::string formatNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", value);
  return text;
}

std::string quote(const std::string& field) {
  std::string quoted(1, '\'');
  quoted += field;
  quoted += '\'';
  return quoted;
}

// One JSON object of a message: its fields by name, with the names it may hold.
class Fields {
 public:
  Fields(const json& object, std::string prefix, std::initializer_list<const char*> allowed)
      : object_(object), prefix_(std::move(prefix)) {
    for (const auto& [key, value] : object.items()) {
      bool known = false;
      for (const char* name : allowed) known = known || key == name;
      if (!known)
        reject(ErrorCode::BadField, prefix_ + key, "unknown field " + quote(prefix_ + key));
    }
  }

  const json* find(const char* name) const {
    auto it = object_.find(name);
    return it == object_.end() ? nullptr : &*it;
  }
  const json& require(const char* name) const {
    if (const json* value = find(name)) return *value;
    reject(ErrorCode::BadField, path(name), "missing field " + quote(path(name)));
  }
  std::string path(const char* name) const { return prefix_ + name; }

  double number(const char* name, double min, double max) const {
    return checkNumber(require(name), path(name), min, max);
  }
  std::optional<double> optionalNumber(const char* name, double min, double max) const {
    const json* value = find(name);
    if (!value) return std::nullopt;
    return checkNumber(*value, path(name), min, max);
  }
  uint64_t integer(const char* name, uint64_t min, uint64_t max) const {
    return checkInteger(require(name), path(name), min, max);
  }
  std::optional<uint64_t> optionalInteger(const char* name, uint64_t min, uint64_t max) const {
    const json* value = find(name);
    if (!value) return std::nullopt;
    return checkInteger(*value, path(name), min, max);
  }
  uint32_t seq() const { return static_cast<uint32_t>(integer("seq", 0, 0xffffffffu)); }

  glm::vec3 vec3(const char* name) const {
    const json& value = require(name);
    if (!value.is_array() || value.size() != 3)
      reject(ErrorCode::BadField, path(name), quote(path(name)) + " must be [x, y, z]");
    glm::vec3 v;
    for (int i = 0; i < 3; ++i)
      v[i] = static_cast<float>(checkNumber(value[i], path(name), -1e6, 1e6));
    return v;
  }
  std::optional<std::string> optionalString(const char* name, size_t maxLength) const {
    const json* value = find(name);
    if (!value) return std::nullopt;
    if (!value->is_string())
      reject(ErrorCode::BadField, path(name), quote(path(name)) + " must be a string");
    const std::string& text = value->get_ref<const std::string&>();
    if (text.size() > maxLength)
      reject(ErrorCode::OutOfRange, path(name),
             quote(path(name)) + " is longer than " + std::to_string(maxLength) + " bytes");
    return text;
  }

 private:
  static double checkNumber(const json& value, const std::string& field, double min, double max) {
    if (!value.is_number()) reject(ErrorCode::BadField, field, quote(field) + " must be a number");
    double v = value.get<double>();
    if (!std::isfinite(v)) reject(ErrorCode::OutOfRange, field, quote(field) + " must be finite");
    if (v < min || v > max)
      reject(ErrorCode::OutOfRange, field,
             quote(field) + " must be " + formatNumber(min) + " to " + formatNumber(max) +
                 " (got " + formatNumber(v) + ")");
    return v;
  }
  // JSON Schema's integer: any number without a fraction (2.0 is 2). The limits are below 2^53,
  // so comparing as doubles is exact.
  static uint64_t checkInteger(const json& value, const std::string& field, uint64_t min,
                               uint64_t max) {
    double v = value.is_number() ? value.get<double>() : 0.5;
    if (v != std::floor(v))
      reject(ErrorCode::BadField, field, quote(field) + " must be a whole number");
    if (v < double(min) || v > double(max))
      reject(ErrorCode::OutOfRange, field,
             quote(field) + " must be " + std::to_string(min) + " to " + std::to_string(max) +
                 " (got " + value.dump() + ")");
    return uint64_t(v);
  }

  const json& object_;
  std::string prefix_;
};

HelloMessage parseHello(const Fields& f, const Limits& limits) {
  HelloMessage hello;
  const json& protocol = f.require("protocol");
  if (!protocol.is_number()) reject(ErrorCode::BadField, "protocol", "'protocol' must be 1");
  if (protocol != kProtocolVersion)
    reject(ErrorCode::OutOfRange, "protocol",
           "protocol " + protocol.dump() + " is not supported: this daemon speaks 1");
  hello.token = f.optionalString("token", kMaxTokenBytes);
  hello.scene = f.optionalString("scene", 1024);
  const json& viewport = f.require("viewport");
  if (!viewport.is_object())
    reject(ErrorCode::BadField, "viewport", "'viewport' must be {\"width\": W, \"height\": H}");
  Fields v(viewport, "viewport.", {"width", "height"});
  hello.viewport.width = static_cast<uint32_t>(v.integer("width", 16, limits.maxWidth));
  hello.viewport.height = static_cast<uint32_t>(v.integer("height", 16, limits.maxHeight));
  return hello;
}

CameraMessage parseCamera(const Fields& f) {
  CameraMessage camera;
  camera.seq = f.seq();
  camera.position = f.vec3("position");
  camera.target = f.vec3("target");
  if (f.find("up")) camera.up = f.vec3("up");
  glm::vec3 forward = camera.target - camera.position;
  if (glm::length(forward) < 1e-6f)
    reject(ErrorCode::OutOfRange, "target", "'target' must differ from 'position'");
  if (glm::length(glm::cross(glm::normalize(forward), camera.up)) < 1e-4f)
    reject(ErrorCode::OutOfRange, "up", "'up' must not be zero or parallel to the view direction");
  return camera;
}

LensMessage parseLens(const Fields& f) {
  LensMessage lens;
  lens.seq = f.seq();
  lens.focalLengthMm = static_cast<float>(f.number("focal_length_mm", 1.0, 5000.0));
  lens.fNumber = static_cast<float>(f.number("f_number", 0.5, 1e6));
  lens.focusDistance = static_cast<float>(f.number("focus_distance", 0.0, 1e5));
  if (lens.focusDistance <= 0.0f)
    reject(ErrorCode::OutOfRange, "focus_distance", "'focus_distance' must be more than 0");
  lens.blades = static_cast<uint32_t>(f.optionalInteger("blades", 0, 16).value_or(0));
  if (lens.blades == 1 || lens.blades == 2)
    reject(ErrorCode::OutOfRange, "blades", "'blades' must be 0 (a circle) or 3 to 16");
  lens.bladeRotationDeg =
      static_cast<float>(f.optionalNumber("blade_rotation_deg", -1e6, 1e6).value_or(0.0));
  auto width = f.optionalNumber("sensor_width_mm", kMinSensorMm, kMaxSensorMm);
  auto height = f.optionalNumber("sensor_height_mm", kMinSensorMm, kMaxSensorMm);
  if (width.has_value() != height.has_value())
    reject(ErrorCode::BadField, width ? "sensor_height_mm" : "sensor_width_mm",
           "give both 'sensor_width_mm' and 'sensor_height_mm', or neither (full frame 36x24)");
  if (width) lens.sensor = {float(*width), float(*height)};
  return lens;
}

FocusAtMessage parseFocusAt(const Fields& f) {
  FocusAtMessage focus;
  focus.seq = f.seq();
  focus.x = static_cast<float>(f.number("x", 0.0, 1e6));
  focus.y = static_cast<float>(f.number("y", 0.0, 1e6));
  focus.pullMs = static_cast<float>(f.optionalNumber("pull_ms", 0.0, 10000.0).value_or(0.0));
  return focus;
}

PickMessage parsePick(const Fields& f) {
  PickMessage pick;
  pick.id = static_cast<uint32_t>(f.integer("id", 0, 0xffffffffu));
  pick.x = static_cast<float>(f.number("x", 0.0, 1e6));
  pick.y = static_cast<float>(f.number("y", 0.0, 1e6));
  return pick;
}

ModeMessage parseMode(const Fields& f) {
  ModeMessage mode;
  mode.seq = f.seq();
  const json& name = f.require("mode");
  std::optional<RenderMode> parsed;
  if (name.is_string()) parsed = parseStreamingMode(name.get<std::string>());
  if (!parsed)
    reject(name.is_string() ? ErrorCode::OutOfRange : ErrorCode::BadField, "mode",
           "'mode' must be one of pinhole, postprocess, raytrace, hybrid");
  mode.mode = *parsed;
  if (const json* view = f.find("view")) {
    std::optional<DebugView> parsedView =
        view->is_string() ? parseDebugView(view->get<std::string>()) : std::nullopt;
    if (!parsedView)
      reject(view->is_string() ? ErrorCode::OutOfRange : ErrorCode::BadField, "view",
             "'view' must be one of " + debugViewNames());
    if (*parsedView != DebugView::Final && mode.mode != RenderMode::Hybrid)
      reject(
          ErrorCode::BadField, "view",
          "the view '" + view->get<std::string>() + "' is a stage of the hybrid: use mode hybrid");
    mode.view = *parsedView;
  }
  return mode;
}

SettingsMessage parseSettings(const Fields& f, const Limits& limits) {
  SettingsMessage settings;
  if (auto q = f.optionalInteger("jpeg_quality_moving", 1, 100))
    settings.jpegQualityMoving = int(*q);
  if (auto q = f.optionalInteger("jpeg_quality_still", 1, 100)) settings.jpegQualityStill = int(*q);
  settings.maxFps = f.optionalNumber("max_fps", 1.0, 240.0);
  if (auto rays = f.optionalInteger("rays_per_pixel", 1, limits.maxRaysPerPixel))
    settings.raysPerPixel = uint32_t(*rays);
  if (auto scale = f.optionalNumber("resolution_scale", 0.25, 1.0))
    settings.resolutionScale = float(*scale);
  return settings;
}

ClientMessage parseObject(const json& object, const Limits& limits) {
  if (!object.is_object())
    reject(ErrorCode::BadJson, "", "a message must be a JSON object with a \"type\"");
  auto type = object.find("type");
  if (type == object.end() || !type->is_string())
    reject(ErrorCode::BadField, "type", "a message needs a \"type\" string");
  const std::string& name = type->get_ref<const std::string&>();
  if (name == "hello")
    return parseHello(Fields(object, "", {"type", "protocol", "token", "viewport", "scene"}),
                      limits);
  if (name == "camera") {
    // The one field this message has lost: say where it went rather than "unknown field".
    if (object.contains("fov_y_deg"))
      reject(ErrorCode::BadField, "fov_y_deg",
             "'fov_y_deg' is not a camera field: the field of view follows the lens, so send "
             "'focal_length_mm' (and the sensor) in a lens message");
    return parseCamera(Fields(object, "", {"type", "seq", "position", "target", "up"}));
  }
  if (name == "lens")
    return parseLens(Fields(object, "",
                            {"type", "seq", "focal_length_mm", "f_number", "focus_distance",
                             "blades", "blade_rotation_deg", "sensor_width_mm",
                             "sensor_height_mm"}));
  if (name == "focus_at")
    return parseFocusAt(Fields(object, "", {"type", "seq", "x", "y", "pull_ms"}));
  if (name == "pick") return parsePick(Fields(object, "", {"type", "id", "x", "y"}));
  if (name == "mode") return parseMode(Fields(object, "", {"type", "seq", "mode", "view"}));
  if (name == "settings")
    return parseSettings(Fields(object, "",
                                {"type", "jpeg_quality_moving", "jpeg_quality_still", "max_fps",
                                 "rays_per_pixel", "resolution_scale"}),
                         limits);
  if (name == "ack")
    return AckMessage{static_cast<uint32_t>(
        Fields(object, "", {"type", "frame"}).integer("frame", 1, 0xffffffffu))};
  std::string shown = name.size() > 64 ? name.substr(0, 64) + "..." : name;
  reject(
      ErrorCode::UnknownType, "type",
      "unknown message type '" + shown + "' (hello, camera, lens, focus_at, pick, mode, settings, ack)");
}

}  // namespace

std::optional<RenderMode> parseStreamingMode(const std::string& name) {
  for (RenderMode mode : kStreamingModes)
    if (name == modeName(mode)) return mode;
  return std::nullopt;
}

const char* errorCodeName(ErrorCode code) {
  switch (code) {
    case ErrorCode::BadJson:
      return "bad_json";
    case ErrorCode::UnknownType:
      return "unknown_type";
    case ErrorCode::BadField:
      return "bad_field";
    case ErrorCode::OutOfRange:
      return "out_of_range";
    case ErrorCode::NotAllowed:
      return "not_allowed";
    case ErrorCode::Busy:
      return "busy";
  }
  return "?";
}

ParsedMessage parseClientMessage(std::string_view text, const Limits& limits) {
  ParsedMessage result;
  if (text.size() > limits.maxMessageBytes) {
    result.error = {ErrorCode::OutOfRange, "the message is longer than " +
                                               std::to_string(limits.maxMessageBytes) + " bytes"};
    return result;
  }
  json object = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (object.is_discarded()) {
    result.error = {ErrorCode::BadJson, "the message is not valid JSON", ""};
    return result;
  }
  try {
    result.message = parseObject(object, limits);
  } catch (const Rejected& rejected) {
    result.error = rejected.error;
  } catch (const std::exception& e) {  // nlohmann type errors the checks above should prevent
    result.error = {ErrorCode::BadField,
                    std::string("the message does not fit its type: ") + e.what(), ""};
  }
  return result;
}

}  // namespace hdof::net
