// The v1 wire protocol (protocol/README.md) as C++ values: the client's messages after
// validation, the error the server answers a bad one with, and the limits they are checked against.
#pragma once

#include "render/modes.h"
#include "render/frame_pipeline.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <variant>

namespace hdof::net {

constexpr int kProtocolVersion = 1;
constexpr const char* kSubprotocol = "hdof.v1";
constexpr const char* kSessionPath = "/session";
constexpr size_t kMaxTokenBytes = 256;  // hello.token; a longer configured token could never match

// WebSocket close codes the daemon uses (RFC 6455, 7.4.1).
enum CloseCode : uint16_t {
  kCloseNormal = 1000,
  kCloseGoingAway = 1001,        // the daemon shuts down
  kCloseProtocolError = 1002,    // no hello first, binary from the client
  kClosePolicyViolation = 1008,  // missing or wrong token, origin not allowed
  kCloseMessageTooBig = 1009,    // a message over max_message_bytes
  kCloseInternalError = 1011,    // the session's rendering failed
  kCloseTryAgainLater = 1013,    // too many sessions
};

// What the daemon accepts; sent to the client in `welcome`.
struct Limits {
  uint32_t maxWidth = 1920, maxHeight = 1080;
  uint32_t maxRaysPerPixel = 16;
  uint32_t maxMessageBytes = 16384;
  uint32_t maxUnackedFrames = 2;
};

struct Viewport {
  uint32_t width = 0, height = 0;
};

struct HelloMessage {
  std::optional<std::string> token;
  Viewport viewport;
  std::optional<std::string> scene;
};

struct CameraMessage {
  uint32_t seq = 0;
  glm::vec3 position{0.0f}, target{0.0f, 0.0f, -1.0f}, up{0.0f, 1.0f, 0.0f};
};

struct LensMessage {
  uint32_t seq = 0;
  float focalLengthMm = 50.0f, fNumber = 2.8f, focusDistance = 5.0f;
  uint32_t blades = 0;
  float bladeRotationDeg = 0.0f;
  Sensor sensor;  // full frame unless the message names one
};

struct FocusAtMessage {
  uint32_t seq = 0;
  float x = 0.0f, y = 0.0f;  // viewport pixels; checked against the session's viewport
  float pullMs = 0.0f;
};

// Asks where the surface under a viewport pixel is, in the session's newest camera; answered by
// `picked` with the same id (the client's orbit pivot and dolly target). Changes nothing.
struct PickMessage {
  uint32_t id = 0;
  float x = 0.0f, y = 0.0f;  // viewport pixels; checked against the session's viewport
};

struct ModeMessage {
  uint32_t seq = 0;
  RenderMode mode = RenderMode::Hybrid;
  DebugView view = DebugView::Final;
};

// Only the fields the client sent are set.
struct SettingsMessage {
  std::optional<int> jpegQualityMoving, jpegQualityStill;
  std::optional<double> maxFps;
  std::optional<uint32_t> raysPerPixel;
  std::optional<float> resolutionScale;
};

struct AckMessage {
  uint32_t frame = 0;
};

using ClientMessage = std::variant<HelloMessage, CameraMessage, LensMessage, FocusAtMessage,
                                   ModeMessage, SettingsMessage, AckMessage, PickMessage>;

enum class ErrorCode { BadJson, UnknownType, BadField, OutOfRange, NotAllowed, Busy };
const char* errorCodeName(ErrorCode code);

struct ProtocolError {
  ErrorCode code = ErrorCode::BadJson;
  std::string message;  // one line for a person
  std::string field;    // the offending field ("viewport.width"), or empty
};

// The modes a client may ask for, in the order welcome lists them (reference is for stills).
inline constexpr RenderMode kStreamingModes[] = {RenderMode::Pinhole, RenderMode::PostProcess,
                                                 RenderMode::RayTrace, RenderMode::Hybrid};

}  // namespace hdof::net
