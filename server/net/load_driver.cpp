#include "net/load_driver.h"

#include "net/message_codec.h"
#include "net/server_messages.h"
#include "net/session_state.h"
#include "net/ws_client.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <deque>
#include <random>
#include <thread>

namespace hdof::net {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

constexpr auto kConnectTimeout = 10s;
constexpr auto kWelcomeTimeout = 30s;
constexpr double kSwayMetres = 0.2, kSwaySeconds = 4.0;

json array(const glm::vec3& v) { return json::array({v.x, v.y, v.z}); }

struct Input {
  uint32_t seq = 0;
  std::string text;
};

// The session's inputs over time: the camera path, or a sideways sway of the starting view.
class InputScript {
 public:
  InputScript(const LoadOptions& options, const json& welcome)
      : options_(options), welcomeCamera_(welcome["camera"]) {
    ParsedMessage camera = parseClientMessage(welcomeCamera_.dump(), Limits{});
    ParsedMessage lens = parseClientMessage(welcome["lens"].dump(), Limits{});
    if (camera.ok()) baseCamera_ = cameraOf(std::get<CameraMessage>(*camera.message), Camera{});
    if (lens.ok()) baseLens_ = lensOf(std::get<LensMessage>(*lens.message));
    if (options.cameraPath)
      for (const CameraKeyframe& key : options.cameraPath->keyframes())
        pathSetsLens_ |= key.focalLengthMm || key.fNumber || key.focusDistance;
  }

  // The messages for time t (seconds since the start); each takes the next seq.
  std::vector<Input> messagesAt(double t, uint32_t& seq) const {
    std::vector<json> messages;
    if (!options_.cameraPath) {
      json camera = welcomeCamera_;
      double dx = kSwayMetres * std::sin(2.0 * M_PI * t / kSwaySeconds);
      camera["position"][0] = camera["position"][0].get<double>() + dx;
      camera["target"][0] = camera["target"][0].get<double>() + dx;
      messages.push_back(camera);
    } else {
      double fraction = std::fmod(t, options_.pathSeconds) / options_.pathSeconds;
      Camera camera;
      Lens lens;
      options_.cameraPath->sample(float(fraction), baseCamera_, baseLens_, camera, lens);
      CameraMessage view = cameraMessageOf(camera, lens.focusDistance);
      messages.push_back({{"type", "camera"},
                          {"position", array(view.position)},
                          {"target", array(view.target)},
                          {"up", array(view.up)}});
      if (pathSetsLens_)
        messages.push_back({{"type", "lens"},
                            {"focal_length_mm", lens.focalLengthMm},
                            {"f_number", lens.fNumber},
                            {"focus_distance", lens.focusDistance},
                            {"sensor_width_mm", lens.sensor.widthMm},
                            {"sensor_height_mm", lens.sensor.heightMm}});
    }
    std::vector<Input> inputs;
    for (json& message : messages) {
      message["seq"] = ++seq;
      inputs.push_back({seq, message.dump()});
    }
    return inputs;
  }

 private:
  const LoadOptions& options_;
  json welcomeCamera_;
  Camera baseCamera_;
  Lens baseLens_;
  bool pathSetsLens_ = false;
};

std::string runId() {
  std::random_device random;
  char id[16];
  std::snprintf(id, sizeof(id), "%08x", random());
  return id;
}

// The welcome, or nothing with result.failure set.
std::optional<json> helloAndWelcome(WsClient& client, const LoadOptions& options,
                                    LoadSessionResult& result) {
  json hello = {{"type", "hello"},
                {"protocol", kProtocolVersion},
                {"viewport", {{"width", options.width}, {"height", options.height}}}};
  if (!options.token.empty()) hello["token"] = options.token;
  client.sendText(hello.dump());
  auto deadline = Clock::now() + kWelcomeTimeout;
  while (Clock::now() < deadline) {
    auto message = client.receive(
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()));
    if (!message) break;
    if (message->kind == WsMessage::Kind::Closed) {
      result.failure = "closed before the welcome (" + std::to_string(message->closeCode) + " " +
                       message->closeReason + ")";
      return std::nullopt;
    }
    if (message->kind != WsMessage::Kind::Text) continue;
    json text = json::parse(message->text, nullptr, false);
    if (text.value("type", "") == "welcome") return text;
    if (text.value("type", "") == "error") {
      result.failure = "refused: " + text.value("message", text.dump());
      return std::nullopt;
    }
  }
  result.failure = "no welcome within " + std::to_string(kWelcomeTimeout.count()) + " s";
  return std::nullopt;
}

void runSession(const LoadOptions& options, const std::string& run, LoadSessionResult& result) {
  WsClientOptions connect;
  connect.host = options.host;
  connect.port = options.port;
  connect.path = options.path + (options.path.find('?') == std::string::npos ? "?" : "&") +
                 "affinity=" + run + "-" + std::to_string(result.index);
  WsClient client(connect);
  if (!client.connected(kConnectTimeout)) {
    auto closed = client.receive(0ms);
    result.failure = "cannot connect to ws://" + options.host + ":" + std::to_string(options.port) +
                     options.path + ": " +
                     (closed && !closed->closeReason.empty() ? closed->closeReason : "timed out");
    return;
  }
  result.connected = true;
  std::optional<json> welcome = helloAndWelcome(client, options, result);
  if (!welcome) return;

  uint32_t seq = 0;
  std::deque<std::pair<uint32_t, Clock::time_point>> pending;  // seqs sent, not yet in a frame
  auto send = [&](const Input& input) {
    client.sendText(input.text);
    pending.emplace_back(input.seq, Clock::now());
    ++result.inputsSent;
  };
  if (!options.mode.empty()) {
    ++seq;
    send({seq, json{{"type", "mode"}, {"seq", seq}, {"mode", options.mode}}.dump()});
  }
  InputScript script(options, *welcome);
  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(1.0 / options.inputHz));
  Clock::time_point start = Clock::now();
  Clock::time_point end = start + std::chrono::duration_cast<Clock::duration>(
                                      std::chrono::duration<double>(options.durationS));
  Clock::time_point nextInput = result.still ? end : start;  // a still view sends no input
  for (Clock::time_point now = start; now < end; now = Clock::now()) {
    if (now >= nextInput) {
      double t = std::chrono::duration<double>(now - start).count();
      for (const Input& input : script.messagesAt(t, seq)) send(input);
      nextInput = std::max(nextInput + period, now);  // late ticks are skipped, not bunched
    }
    auto wait = std::min(nextInput, end) - Clock::now();
    auto message = client.receive(std::max(
        std::chrono::duration_cast<std::chrono::milliseconds>(wait), std::chrono::milliseconds(0)));
    if (!message) continue;
    if (message->kind == WsMessage::Kind::Closed) {
      result.failure = "closed by the daemon (" + std::to_string(message->closeCode) + " " +
                       message->closeReason + ")";
      ++result.errors;
      result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
      return;
    }
    if (message->kind == WsMessage::Kind::Text) {
      if (json::parse(message->text, nullptr, false).value("type", "") == "error") ++result.errors;
      continue;
    }
    Clock::time_point received = Clock::now();
    auto frame = parseFrameMessage(message->binary);
    if (!frame) {
      ++result.errors;
      continue;
    }
    ++result.frames;
    result.bytes += message->binary.size();
    result.renderScales.push_back(double(frame->header.width) / double(options.width));
    client.sendText(json{{"type", "ack"}, {"frame", frame->header.frame}}.dump());
    while (!pending.empty() && pending.front().first <= frame->header.seq) {
      if (pending.front().first == frame->header.seq)
        result.latenciesMs.push_back(
            std::chrono::duration<double, std::milli>(received - pending.front().second).count());
      pending.pop_front();
    }
  }
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  result.completed = true;
  client.close();
  for (auto message = client.receive(2s); message && message->kind != WsMessage::Kind::Closed;)
    message = client.receive(2s);
}

}  // namespace

std::vector<LoadSessionResult> runLoad(const LoadOptions& options) {
  std::vector<LoadSessionResult> results(options.sessions + options.stillSessions);
  std::string run = options.affinity.empty() ? runId() : options.affinity;
  std::vector<std::thread> threads;
  for (uint32_t i = 0; i < results.size(); ++i) {
    results[i].index = i + 1;
    results[i].still = i >= options.sessions;
    threads.emplace_back([&, i] { runSession(options, run, results[i]); });
  }
  for (std::thread& thread : threads) thread.join();
  return results;
}

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  size_t rank = size_t(std::ceil(std::clamp(q, 0.0, 1.0) * double(values.size())));
  return values[std::max<size_t>(rank, 1) - 1];
}

}  // namespace hdof::net
