// hdof serve's settings: built-in defaults, then the JSON config file (--config), then the
// command line. The config file is one JSON object whose keys are the snake_case names below.
#pragma once

#include "net/session_state.h"

#include <string>
#include <vector>

namespace hdof {

struct ServeConfig {
  std::string bind = "127.0.0.1";  // bind
  uint32_t port = 8080;            // port (0: any free port)
  std::string scene = "builtin:dof";
  std::string webRoot = HDOF_WEB_ROOT;  // web_root
  std::string token;
  std::vector<std::string> allowedOrigins;  // allowed_origins
  std::vector<std::string> allowedHosts;    // allowed_hosts
  bool allowInsecureToken = false;          // allow_insecure_token
  uint32_t maxSessions = 8;                 // max_sessions
  net::Limits limits;            // max_width, max_height, max_rays_per_pixel, max_message_bytes,
                                 // max_unacked_frames
  uint32_t clientTimeoutS = 30;  // client_timeout_s
  uint32_t helloTimeoutS = 10;   // hello_timeout_s
  uint32_t encodeThreads = 2;    // encode_threads
  uint32_t renderStallS = 30;    // render_stall_s: a frame this long makes /healthz fail
  std::string mode = "hybrid";   // a session's first mode
  net::StreamSettings stream;    // jpeg_quality_moving, jpeg_quality_still, max_fps, rays_per_pixel
  uint32_t accumulationFrames = 64;  // accumulation_frames
  double stillAfterMs = 150.0;       // still_after_ms
  double targetFps = 20.0;           // target_fps (0: no interactive resolution)
};

// Reads a config object from JSON text over `base`; `source` names the text in messages.
// Throws UsageError naming the key on unknown keys, wrong types and values out of range.
ServeConfig parseServeConfig(const std::string& text, const std::string& source,
                             ServeConfig base = {});
// Reads the file; a missing or unreadable file is a UsageError too.
ServeConfig loadServeConfig(const std::string& path);
// Checks the values that depend on each other (rays_per_pixel within max_rays_per_pixel, ...).
void checkServeConfig(const ServeConfig& config, const std::string& source);
// Checks the access settings once flags, environment and file are merged: a token hello can
// carry (at most 256 bytes), and a token on an address other machines reach only with
// allow_insecure_token (it would cross the network in clear text unless a proxy in front
// terminates TLS). Throws UsageError.
void checkServeAccess(const ServeConfig& config);

}  // namespace hdof
