// What the daemon sends: `welcome` and `error` text messages, and the binary frame message
// (32-byte header, JSON stats, JPEG) with its parser for clients. Pure functions, no network.
#pragma once

#include "net/protocol.h"
#include "render/camera.h"
#include "render/focus_pick.h"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hdof::net {

struct Welcome {
  std::string session;
  Limits limits;
  std::string sceneName;
  Aabb bounds;
  std::vector<SceneCamera> cameras;
  Camera camera;  // the starting view
  Lens lens;
  Viewport viewport;  // the session's: the field of view in force follows from it and the lens
};

// Text the daemon did not write itself (a scene path, a glTF camera name, a client's field) may
// not be UTF-8: it is sent with U+FFFD in place of the bad bytes, never an exception.
std::string welcomeMessage(const Welcome& welcome);
std::string errorMessage(const ProtocolError& error);
// The answer to `pick` id: the surface's point and distances, or `hit` false on the background.
std::string pickedMessage(uint32_t id, const std::optional<SurfaceHit>& hit);

// Valid UTF-8 (bad bytes become '?') of at most maxBytes, cut between characters: a close
// frame's reason (RFC 6455: 123 bytes), which browsers require to be UTF-8.
std::string utf8Prefix(std::string_view text, size_t maxBytes);

// The camera and lens in the client's message form (what `welcome` starts the client with).
CameraMessage cameraMessageOf(const Camera& camera, float targetDistance = 1.0f);
LensMessage lensMessageOf(const Lens& lens);

constexpr uint32_t kFrameMagic = 0x464F4448;  // "HDOF" in little-endian byte order
constexpr uint16_t kFrameFormatJpeg = 1;
constexpr size_t kFrameHeaderBytes = 32;

struct FrameHeader {
  uint32_t frame = 0;
  uint32_t width = 0, height = 0;
  uint32_t seq = 0;  // the last input seq applied
};

// The stats of one frame (frame-stats.json); fields without a value are left out.
struct FrameStatsMessage {
  uint32_t frame = 0;
  std::string mode;
  std::vector<std::pair<std::string, double>> passesMs;
  double gpuMs = 0.0;
  double renderMs = 0.0;  // wall clock, submit to finish
  uint64_t raysShot = 0;
  double maskCoverage = 0.0;
  double encodeMs = 0.0;
  double queueWaitMs = 0.0;
  uint64_t bytes = 0;                   // the JPEG's size
  std::optional<double> inputToSendMs;  // only frames that apply a new input
  int jpegQuality = 0;
  uint32_t accumulatedFrames = 0;
  uint32_t accumulationTarget = 0;  // frames of a still view, after which it has converged
  bool moving = false;              // the view changed within still_after_ms
  float focusDistance = 0.0f;
  float renderScale = 1.0f;  // the frame's size over the viewport's
  glm::vec2 fovDeg{0.0f};    // the field of view in force (horizontal, vertical)
};

std::string frameStatsJson(const FrameStatsMessage& stats);

// header + stats + jpeg, after `headroom` zero bytes (libwebsockets writes its own header there).
std::vector<uint8_t> frameMessage(const FrameHeader& header, const std::string& stats,
                                  std::span<const uint8_t> jpeg, size_t headroom = 0);

struct ParsedFrame {
  FrameHeader header;
  std::string stats;              // JSON
  std::span<const uint8_t> jpeg;  // into the message
};

// Reads a frame message; nothing when it is not one (wrong magic, version or lengths).
std::optional<ParsedFrame> parseFrameMessage(std::span<const uint8_t> message);

}  // namespace hdof::net
