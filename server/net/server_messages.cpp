#include "net/server_messages.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>

namespace hdof::net {
namespace {

using nlohmann::json;

json array(const glm::vec3& v) { return json::array({v.x, v.y, v.z}); }

json cameraJson(const CameraMessage& camera) {
  return {{"type", "camera"},
          {"seq", camera.seq},
          {"position", array(camera.position)},
          {"target", array(camera.target)},
          {"up", array(camera.up)}};
}

void put32(uint8_t* out, uint32_t value) {
  for (int i = 0; i < 4; ++i) out[i] = uint8_t(value >> (8 * i));
}
void put16(uint8_t* out, uint16_t value) {
  out[0] = uint8_t(value);
  out[1] = uint8_t(value >> 8);
}
uint32_t get32(const uint8_t* in) {
  return uint32_t(in[0]) | uint32_t(in[1]) << 8 | uint32_t(in[2]) << 16 | uint32_t(in[3]) << 24;
}
uint16_t get16(const uint8_t* in) { return uint16_t(in[0] | in[1] << 8); }

}  // namespace

CameraMessage cameraMessageOf(const Camera& camera, float targetDistance) {
  CameraMessage message;
  message.position = camera.position;
  message.target = camera.position + camera.forward * targetDistance;
  message.up = camera.up;
  return message;
}

LensMessage lensMessageOf(const Lens& lens) {
  LensMessage message;
  message.focalLengthMm = lens.focalLengthMm;
  message.fNumber = lens.fNumber;
  message.focusDistance = lens.focusDistance;
  message.blades = lens.blades;
  message.bladeRotationDeg = glm::degrees(lens.bladeRotation);
  message.sensor = lens.sensor;
  return message;
}

std::string welcomeMessage(const Welcome& welcome) {
  json modes = json::array();
  for (RenderMode mode : kStreamingModes) modes.push_back(modeName(mode));
  json views = debugViewList();
  json cameras = json::array();
  for (const SceneCamera& c : welcome.cameras) {
    json camera = cameraJson(cameraMessageOf(Camera::fromScene(c), c.focusDistance.value_or(1.0f)));
    camera.erase("type");
    camera.erase("seq");
    camera["name"] = c.name;
    // What the client's scene-camera picker turns into a focal length on its sensor.
    camera["fov_y_deg"] = glm::degrees(c.yfov);
    if (c.focusDistance) camera["focus_distance"] = *c.focusDistance;
    cameras.push_back(camera);
  }
  LensMessage lens = lensMessageOf(welcome.lens);
  glm::vec2 fov = fieldOfViewDeg(welcome.lens, welcome.viewport.width, welcome.viewport.height);
  json message = {
      {"type", "welcome"},
      {"protocol", kProtocolVersion},
      {"session", welcome.session},
      {"limits",
       {{"max_width", welcome.limits.maxWidth},
        {"max_height", welcome.limits.maxHeight},
        {"max_rays_per_pixel", welcome.limits.maxRaysPerPixel},
        {"max_message_bytes", welcome.limits.maxMessageBytes},
        {"max_unacked_frames", welcome.limits.maxUnackedFrames}}},
      {"modes", modes},
      {"views", views},
      {"scene",
       {{"name", welcome.sceneName},
        {"bounds", {{"min", array(welcome.bounds.min)}, {"max", array(welcome.bounds.max)}}},
        {"cameras", cameras}}},
      {"camera", cameraJson(cameraMessageOf(welcome.camera, welcome.lens.focusDistance))},
      {"lens",
       {{"type", "lens"},
        {"seq", 0},
        {"focal_length_mm", lens.focalLengthMm},
        {"f_number", lens.fNumber},
        {"focus_distance", lens.focusDistance},
        {"blades", lens.blades},
        {"blade_rotation_deg", lens.bladeRotationDeg},
        {"sensor_width_mm", lens.sensor.widthMm},
        {"sensor_height_mm", lens.sensor.heightMm}}},
      {"fov_x_deg", fov.x},
      {"fov_y_deg", fov.y}};
  return message.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string errorMessage(const ProtocolError& error) {
  json message = {
      {"type", "error"}, {"code", errorCodeName(error.code)}, {"message", error.message}};
  if (!error.field.empty()) message["field"] = error.field;
  // Replace, not throw, if a message quotes bytes of the client's that are not UTF-8.
  return message.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string pickedMessage(uint32_t id, const std::optional<SurfaceHit>& hit) {
  json message = {{"type", "picked"}, {"id", id}, {"hit", hit.has_value()}};
  if (hit) {
    message["point"] = array(hit->point);
    message["depth"] = hit->depth;
    message["distance"] = hit->distance;
  }
  return message.dump();
}

std::string utf8Prefix(std::string_view text, size_t maxBytes) {
  std::string out;
  for (size_t i = 0; i < text.size();) {
    auto byte = [&](size_t at) { return static_cast<unsigned char>(text[at]); };
    unsigned char lead = byte(i);
    size_t length = lead < 0x80           ? 1
                    : (lead >> 5) == 0x6  ? 2
                    : (lead >> 4) == 0xE  ? 3
                    : (lead >> 3) == 0x1E ? 4
                                          : 0;
    bool valid = length > 0 && i + length <= text.size();
    for (size_t k = 1; valid && k < length; ++k) valid = (byte(i + k) & 0xC0) == 0x80;
    if (valid && length > 1) {
      // No overlong forms, no surrogates, nothing above U+10FFFF.
      uint32_t code = lead & (0x7F >> length);
      for (size_t k = 1; k < length; ++k) code = code << 6 | (byte(i + k) & 0x3F);
      static constexpr uint32_t kSmallest[] = {0, 0, 0x80, 0x800, 0x10000};
      valid = code >= kSmallest[length] && code <= 0x10FFFF && (code < 0xD800 || code > 0xDFFF);
    }
    size_t take = valid ? length : 1;
    if (out.size() + take > maxBytes) break;
    if (valid)
      out.append(text.substr(i, length));
    else
      out += '?';
    i += take;
  }
  return out;
}

std::string frameStatsJson(const FrameStatsMessage& stats) {
  json passes = json::object();
  for (const auto& [name, ms] : stats.passesMs) passes[name] = ms;
  json message = {{"frame", stats.frame},
                  {"mode", stats.mode},
                  {"passes_ms", passes},
                  {"gpu_ms", stats.gpuMs},
                  {"render_ms", stats.renderMs},
                  {"rays_shot", stats.raysShot},
                  {"mask_coverage", stats.maskCoverage},
                  {"encode_ms", stats.encodeMs},
                  {"queue_wait_ms", stats.queueWaitMs},
                  {"bytes", stats.bytes},
                  {"jpeg_quality", stats.jpegQuality},
                  {"accumulated_frames", stats.accumulatedFrames},
                  {"accumulation_target", stats.accumulationTarget},
                  {"moving", stats.moving},
                  {"focus_distance", stats.focusDistance},
                  {"render_scale", stats.renderScale},
                  {"fov_x_deg", stats.fovDeg.x},
                  {"fov_y_deg", stats.fovDeg.y}};
  if (stats.inputToSendMs) message["input_to_send_ms"] = *stats.inputToSendMs;
  return message.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::vector<uint8_t> frameMessage(const FrameHeader& header, const std::string& stats,
                                  std::span<const uint8_t> jpeg, size_t headroom) {
  std::vector<uint8_t> message(headroom + kFrameHeaderBytes + stats.size() + jpeg.size());
  uint8_t* out = message.data() + headroom;
  put32(out + 0, kFrameMagic);
  put16(out + 4, uint16_t(kProtocolVersion));
  put16(out + 6, kFrameFormatJpeg);
  put32(out + 8, header.frame);
  put32(out + 12, header.width);
  put32(out + 16, header.height);
  put32(out + 20, header.seq);
  put32(out + 24, uint32_t(stats.size()));
  put32(out + 28, 0);
  std::memcpy(out + kFrameHeaderBytes, stats.data(), stats.size());
  if (!jpeg.empty()) std::memcpy(out + kFrameHeaderBytes + stats.size(), jpeg.data(), jpeg.size());
  return message;
}

std::optional<ParsedFrame> parseFrameMessage(std::span<const uint8_t> message) {
  if (message.size() < kFrameHeaderBytes) return std::nullopt;
  const uint8_t* in = message.data();
  if (get32(in) != kFrameMagic || get16(in + 4) != kProtocolVersion ||
      get16(in + 6) != kFrameFormatJpeg)
    return std::nullopt;
  uint32_t statsBytes = get32(in + 24);
  if (statsBytes > message.size() - kFrameHeaderBytes) return std::nullopt;
  ParsedFrame frame;
  frame.header = {get32(in + 8), get32(in + 12), get32(in + 16), get32(in + 20)};
  frame.stats.assign(reinterpret_cast<const char*>(in + kFrameHeaderBytes), statsBytes);
  frame.jpeg = message.subspan(kFrameHeaderBytes + statsBytes);
  return frame;
}

}  // namespace hdof::net
