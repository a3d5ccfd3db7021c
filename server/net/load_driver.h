// The scripted load of `hdof load`: N concurrent WebSocket sessions against a daemon (or a proxy
// in front of several), each moving its camera at a steady rate as a user dragging would, along
// a camera path or a sway of the starting view, and acking every frame on receipt as the browser
// client does; optionally beside sessions that hold their view still and take what the daemon
// sends while it refines it. Measures per session: frames, bytes, input-to-frame latency (from
// sending a seq to receiving the first frame that carries it) and errors.
#pragma once

#include "render/camera_path.h"

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hdof::net {

struct LoadOptions {
  std::string host = "127.0.0.1";
  int port = 0;
  std::string path = "/session";  // may carry a query; each session adds affinity=KEY-INDEX
  std::string affinity;           // KEY: a proxy's session key (empty: a random one per run)
  uint32_t sessions = 1;
  uint32_t stillSessions = 0;  // more sessions that hold their starting view still (no input)
  double durationS = 10.0;
  double inputHz = 30.0;                 // camera messages per second and session
  std::optional<CameraPath> cameraPath;  // one loop takes pathSeconds; else a sway
  double pathSeconds = 10.0;
  std::string mode;  // empty: the daemon's default
  uint32_t width = 640, height = 360;
  std::string token;
};

struct LoadSessionResult {
  uint32_t index = 0;
  bool still = false;  // held its starting view still, letting the daemon refine it
  bool connected = false;
  bool completed = false;  // ran its whole duration
  std::string failure;     // why not, in one line
  uint64_t frames = 0, bytes = 0, errors = 0, inputsSent = 0;
  double seconds = 0.0;             // from the welcome to the end
  std::vector<double> latenciesMs;  // input to frame, one per seq that came back in a frame
  std::vector<double> renderScales;  // each frame's width over the viewport's

  double framesPerSecond() const { return seconds > 0.0 ? double(frames) / seconds : 0.0; }
  double bytesPerSecond() const { return seconds > 0.0 ? double(bytes) / seconds : 0.0; }
};

// Runs every session on its own thread and returns when all are done.
std::vector<LoadSessionResult> runLoad(const LoadOptions& options);

// The value at fraction q (0..1) of the values, nearest rank; 0 for none.
double percentile(std::vector<double> values, double q);

}  // namespace hdof::net
