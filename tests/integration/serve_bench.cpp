// hdof_serve_bench: the daemon's streaming figures for one session. It starts hdof serve (or
// connects to --port), asks for a mode and size, moves the camera 60 times a second as a mouse
// drag would and acks every frame at once, so the daemon always has a changed view to render;
// then prints the frame rate and the medians of the frames' stats. Compare serve_fps with
// 1000 / postprocess_frame_wall_ms of `hdof bench` at the same size.
#include "app/cli.h"
#include "daemon.h"
#include "render/frame_pipeline.h"

#include <algorithm>
#include <cstdio>

using namespace hdof;
using namespace hdof::test;

namespace {

double medianOf(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

int run(std::span<const std::string> args) {
  std::string mode = "postprocess", size = "640x360";
  uint32_t seconds = 10, rays = 4, port = 0;
  ArgParser parser("serve_bench", "[options]",
                   "Streams one session from hdof serve and prints frames per second, encode\n"
                   "and input-to-send times (medians, after one second of warm-up).");
  parser.option("--mode", "MODE", "pinhole|postprocess|raytrace|hybrid (default postprocess)",
                &mode);
  parser.option("--size", "WxH", "viewport (default 640x360)", &size);
  parser.option("--seconds", "N", "measured time (default 10)", &seconds);
  parser.option("--rays", "N", "rays per pixel (default 4, as hdof bench compares modes)", &rays);
  parser.option("--port", "P", "a running daemon on 127.0.0.1 (default: start one)", &port);
  if (!parser.parse(args)) return 0;
  Size2 viewport = parseSize(size, 4096);

  std::optional<Daemon> daemon;
  if (port == 0) {
    daemon.emplace(DaemonOptions{{}, R"({"max_width": 4096, "max_height": 4096})", {}});
    port = uint32_t(daemon->port());
  }
  net::WsClientOptions options;
  options.port = int(port);
  net::WsClient client(options);
  if (!client.connected(kTimeout)) throw std::runtime_error("no connection to the daemon");
  client.sendText(helloMessage(viewport.width, viewport.height));
  nlohmann::json welcome = nextText(client);
  if (welcome.value("type", "") != "welcome")
    throw std::runtime_error("no welcome: " + welcome.dump());
  client.sendText(
      nlohmann::json{{"type", "settings"}, {"max_fps", 240}, {"rays_per_pixel", rays}}.dump());
  client.sendText(nlohmann::json{{"type", "mode"}, {"seq", 1}, {"mode", mode}}.dump());

  nlohmann::json camera = welcome["camera"];
  uint32_t seq = 1;
  auto moveCamera = [&] {
    camera["seq"] = ++seq;
    camera["position"][0] = camera["position"][0].get<double>() + ((seq / 50) % 2 ? -0.01 : 0.01);
    client.sendText(camera.dump());
  };

  using Clock = std::chrono::steady_clock;
  Clock::time_point start = Clock::now(), measureFrom = start + std::chrono::seconds(1);
  Clock::time_point end = measureFrom + std::chrono::seconds(seconds);
  Clock::time_point nextMove = start;
  std::vector<double> encodeMs, inputToSendMs, gpuMs, queueWaitMs;
  uint32_t frames = 0;
  for (Clock::time_point now = start; now < end; now = Clock::now()) {
    if (now >= nextMove) {  // a mouse drag's camera updates, at 60 Hz
      moveCamera();
      nextMove += std::chrono::microseconds(16667);
    }
    auto message = client.receive(
        std::chrono::duration_cast<std::chrono::milliseconds>(nextMove - Clock::now()));
    if (!message || message->kind != net::WsMessage::Kind::Binary) {
      if (message && message->kind == net::WsMessage::Kind::Closed)
        throw std::runtime_error("the daemon closed the session: " + message->closeReason);
      continue;
    }
    auto frame = net::parseFrameMessage(message->binary);
    if (!frame) throw std::runtime_error("a binary message that is not a frame");
    ack(client, frame->header.frame);
    nlohmann::json stats = nlohmann::json::parse(frame->stats);
    if (Clock::now() < measureFrom || stats.value("mode", "") != mode) continue;
    ++frames;
    encodeMs.push_back(stats["encode_ms"]);
    gpuMs.push_back(stats["gpu_ms"]);
    queueWaitMs.push_back(stats["queue_wait_ms"]);
    if (stats.contains("input_to_send_ms")) inputToSendMs.push_back(stats["input_to_send_ms"]);
  }
  double fps = frames / std::chrono::duration<double>(end - measureFrom).count();
  std::printf(
      "mode=%s size=%ux%u rays_per_pixel=%u frames=%u serve_fps=%.2f frame_interval_ms=%.1f\n"
      "encode_ms=%.3f input_to_send_ms=%.1f gpu_ms=%.1f queue_wait_ms=%.2f (medians)\n",
      mode.c_str(), viewport.width, viewport.height, rays, frames, fps, 1000.0 / fps,
      medianOf(encodeMs), medianOf(inputToSendMs), medianOf(gpuMs), medianOf(queueWaitMs));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(std::vector<std::string>(argv + 1, argv + argc));
  } catch (const UsageError& e) {
    std::fprintf(stderr, "serve_bench: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "serve_bench: %s\n", e.what());
    return 1;
  }
}
