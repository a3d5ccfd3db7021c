// The daemon against attacks and faults, each written as the attack: a non-reader that forges
// acks, upgrades without the subprotocol, foreign origins and Host headers, other HTTP methods,
// symlinks out of the web root, a render thread or device that fails, a signal during start-up,
// a scene whose name is not UTF-8. No assert depends on timing.
#include "daemon.h"
#include "common/scratch_dir.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

namespace hdof::test {
namespace {

constexpr uint32_t kWidth = 96, kHeight = 54;

// An empty folder of this process's scratch folder.
std::filesystem::path emptyDir(const std::string& name) {
  auto dir = scratchDir("hardening") / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Polls `condition` (up to the generous kTimeout); true once it holds.
template <typename Condition>
bool eventually(Condition condition) {
  auto deadline = std::chrono::steady_clock::now() + kTimeout;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(50ms);
  }
  return true;
}

// 1. A client that never reads, keeps moving the camera and acks every frame it can predict
//    (the counts /metrics shows, and one beyond), and sends unsolicited pongs, as a library that
//    answers pings for it would. Its acks open the window only for frames written to its socket;
//    the socket fills, the session stops being scheduled, and it is cut off after
//    client_timeout_s: the daemon's queued frames stay within max_unacked_frames, its RSS flat.
TEST(Hardening, AForgedAckNonReaderCannotMakeFramesPileUp) {
  Daemon daemon({{},
                 R"({"mode": "pinhole", "max_fps": 240, "jpeg_quality_moving": 100,
                     "jpeg_quality_still": 100, "client_timeout_s": 6})",
                 {}});
  RawConnection attacker(daemon.port());
  ASSERT_TRUE(attacker.handshake());
  ASSERT_TRUE(attacker.sendText(helloMessage(640, 360)));
  ASSERT_TRUE(eventually([&] { return metricValue(daemon.port(), "hdof_frames_sent_total") >= 1; }))
      << daemon.log();
  uint64_t rssBefore = daemon.rssBytes();
  uint64_t rssMost = rssBefore;
  double queuedMost = 0.0, queuedGaugeMost = 0.0;
  bool cutOff = false;
  const std::string pong = std::string("\x8a\x80", 2) + std::string(4, '\0');  // masked, empty
  // Attacks until cut off (about client_timeout_s), for at most half a minute.
  auto giveUp = std::chrono::steady_clock::now() + 30s;
  for (uint32_t seq = 1; !cutOff && std::chrono::steady_clock::now() < giveUp; ++seq) {
    // One snapshot of /metrics: frames rendered, sent and dropped; what is neither sent nor
    // dropped waits inside the daemon.
    std::string metrics = httpGet(daemon.port(), "/metrics").body;
    auto value = [&](const std::string& name) {
      auto at = metrics.find("\n" + name + " ");
      return at == std::string::npos ? 0.0 : std::atof(metrics.c_str() + at + name.size() + 2);
    };
    double rendered = value("hdof_frames_rendered_total");
    double sent = value("hdof_frames_sent_total");
    queuedMost = std::max(queuedMost, rendered - sent - value("hdof_frames_dropped_total"));
    queuedGaugeMost = std::max(queuedGaugeMost, value("hdof_frames_queued"));
    cutOff = value("hdof_sessions_timed_out_total") == 1.0;
    nlohmann::json camera = {{"type", "camera"},
                             {"seq", seq},
                             {"position", {0.001 * (seq % 100), 1.5, 4.0}},
                             {"target", {0.0, 1.0, 0.0}}};
    // Any write may fail once the daemon has hung up.
    attacker.sendText(camera.dump());
    attacker.sendText(nlohmann::json{{"type", "ack"}, {"frame", uint32_t(sent)}}.dump());
    attacker.sendText(nlohmann::json{{"type", "ack"}, {"frame", uint32_t(rendered)}}.dump());
    attacker.sendText(nlohmann::json{{"type", "ack"}, {"frame", uint32_t(rendered) + 1}}.dump());
    attacker.sendBytes(pong);
    rssMost = std::max(rssMost, daemon.rssBytes());
    std::this_thread::sleep_for(5ms);
  }
  std::printf("forged-ack non-reader: frames rendered and not sent at most %.0f, RSS %+.1f MB\n",
              queuedMost, (double(rssMost) - double(rssBefore)) / 1e6);
  EXPECT_TRUE(cutOff) << "a client that never reads is cut off\n" << daemon.log();
  EXPECT_LE(queuedMost, 2.0) << "at most max_unacked_frames frames wait in the daemon";
  EXPECT_LE(queuedGaugeMost, 2.0) << "hdof_frames_queued says the same";
  EXPECT_GE(metricValue(daemon.port(), "hdof_errors_total{code=\"out_of_range\"}"), 1.0)
      << "acks of frames not yet sent are out_of_range";
  if (!kAddressSanitizer) {  // its allocator keeps freed memory and lavapipe's warm-up grows
    EXPECT_LT(double(rssMost) - double(rssBefore), 48e6)
        << "RSS from " << rssBefore << " to " << rssMost << " bytes";
  }
  EXPECT_NE(daemon.log().find("close=timeout"), std::string::npos) << daemon.log();
  EXPECT_EQ(metricValue(daemon.port(), "hdof_sessions"), 0.0);
  // The daemon serves the next client as before.
  auto client = connectSession(daemon.port());
  helloAndWelcome(*client, kWidth, kHeight);
  EXPECT_TRUE(nextFrame(*client)) << daemon.log();
}

// 1b. A non-reader whose frames are small enough that its socket never fills, and that acks by
//     counting (every number up to a guess that keeps growing): it gets frames only until it
//     leaves one of the daemon's pings unanswered for a second, then none while it stays
//     connected (long before client_timeout_s cuts it off).
TEST(Hardening, ACountingForgerIsPausedOnceItLeavesAPingUnanswered) {
  Daemon daemon({{}, R"({"mode": "pinhole", "max_fps": 240, "client_timeout_s": 60})", {}});
  // A client before it has the daemon build its pipelines, so that the forger's first frames
  // come at once (a GPU compiling the shaders afresh can take longer than a ping's grace).
  {
    auto client = connectSession(daemon.port());
    helloAndWelcome(*client, kWidth, kHeight);
    ASSERT_TRUE(nextFrame(*client)) << daemon.log();
  }
  ASSERT_TRUE(eventually([&] { return metricValue(daemon.port(), "hdof_sessions") == 0.0; }));
  double renderedBefore = metricValue(daemon.port(), "hdof_frames_rendered_total");
  RawConnection attacker(daemon.port());
  ASSERT_TRUE(attacker.handshake());
  ASSERT_TRUE(attacker.sendText(helloMessage(kWidth, kHeight)));
  uint32_t guess = 0;
  auto attack = [&] {
    ++guess;
    nlohmann::json camera = {{"type", "camera"},
                             {"seq", guess},
                             {"position", {0.001 * (guess % 100), 1.5, 4.0}},
                             {"target", {0.0, 1.0, 0.0}}};
    attacker.sendText(camera.dump());
    for (uint32_t frame = guess > 8 ? guess - 8 : 1; frame <= guess; ++frame)
      attacker.sendText(nlohmann::json{{"type", "ack"}, {"frame", frame}}.dump());
    std::this_thread::sleep_for(10ms);
  };
  bool paused = eventually([&] {
    attack();
    return metricValue(daemon.port(), "hdof_sessions_not_reading") == 1.0;
  });
  ASSERT_TRUE(paused) << daemon.log();
  double rendered = metricValue(daemon.port(), "hdof_frames_rendered_total");
  EXPECT_GT(rendered, renderedBefore) << "frames until it leaves a ping unanswered";
  for (int i = 0; i < 100; ++i) attack();  // a second more of it
  // The render thread may have been rendering one frame of it when the pause came: that one
  // finishes, no other starts.
  EXPECT_LE(metricValue(daemon.port(), "hdof_frames_rendered_total"), rendered + 1.0)
      << "no frames while it does not answer";
  EXPECT_EQ(metricValue(daemon.port(), "hdof_sessions"), 1.0) << "still connected";
  EXPECT_EQ(metricValue(daemon.port(), "hdof_sessions_timed_out_total"), 0.0);
}

// 2. Only an hdof.v1 upgrade on /session becomes a session; every other upgrade is an HTTP error
//    and counts for nothing.
TEST(Hardening, UpgradesWithoutTheSubprotocolGetAnHttpError) {
  Daemon daemon({{}, R"({"mode": "postprocess", "max_sessions": 1})", {}});
  for (const char* path : {"/", "/index.html", "/healthz", "/metrics", "/session", "/nowhere"})
    for (const char* protocol : {"", "http", "chat", "http, hdof.v1", "hdof.v1"}) {
      if (std::string(path) == "/session" && std::string(protocol) == "hdof.v1") continue;
      RawConnection connection(daemon.port());
      std::vector<std::string> headers;
      if (*protocol) headers.push_back(std::string("Sec-WebSocket-Protocol: ") + protocol);
      int status = connection.upgrade(path, headers);
      EXPECT_GE(status, 400) << path << " [" << protocol << "]";
      EXPECT_LT(status, 500) << path << " [" << protocol << "]";
    }
  EXPECT_EQ(metricValue(daemon.port(), "hdof_sessions_total"), 0.0);
  // max_sessions is 1, and the one session is still there to take.
  RawConnection session(daemon.port());
  EXPECT_EQ(session.upgrade("/session", {"Sec-WebSocket-Protocol: chat, hdof.v1"}), 101);
  auto client = connectSession(daemon.port());
  helloAndWelcome(*client, kWidth, kHeight);
}

// 3. Same origin by default: a page of another site cannot open a session (cross-site WebSocket
//    hijacking), and a Host that is not this machine's is refused (DNS rebinding).
TEST(Hardening, AForeignOriginGetsNoSessionFromADefaultDaemon) {
  Daemon daemon({{}, R"({"mode": "postprocess"})", {}});
  std::string self = "127.0.0.1:" + std::to_string(daemon.port());
  {
    auto evil = connectSession(daemon.port(), "evil.example");  // Origin: http://evil.example
    evil->sendText(helloMessage(kWidth, kHeight));
    nlohmann::json error = nextText(*evil);
    EXPECT_EQ(error.value("code", ""), "not_allowed") << error.dump();
    EXPECT_EQ(error.value("field", ""), "origin") << error.dump();
    EXPECT_EQ(closeCode(*evil), 1008);
  }
  {
    auto sameHostOtherPort = connectSession(daemon.port(), "127.0.0.1:1");
    EXPECT_EQ(closeCode(*sameHostOtherPort), 1008);
  }
  EXPECT_EQ(metricValue(daemon.port(), "hdof_sessions_total"), 0.0);
  auto own = connectSession(daemon.port(), self);  // the daemon's own page
  helloAndWelcome(*own, kWidth, kHeight);
  auto localhost = connectSession(daemon.port(), "localhost:" + std::to_string(daemon.port()));
  helloAndWelcome(*localhost, kWidth, kHeight);
  auto program = connectSession(daemon.port());  // no Origin: not a browser page
  helloAndWelcome(*program, kWidth, kHeight);

  for (const char* path : {"/", "/metrics", "/healthz"}) {
    HttpExchange rebound = httpRequest(daemon.port(), "GET", path, {"Host: evil.example:8080"});
    EXPECT_EQ(rebound.status, 403) << path;
    EXPECT_EQ(rebound.body.find("hdof_"), std::string::npos) << path;
  }
  RawConnection rebound(daemon.port());
  EXPECT_EQ(rebound.upgrade("/session", {"Sec-WebSocket-Protocol: hdof.v1", "Host: evil.example"}),
            403);
  EXPECT_EQ(httpRequest(daemon.port(), "GET", "/healthz", {"Host: localhost"}).status, 200);
}

TEST(Hardening, AllowedOriginsAndHostsLetOthersIn) {
  Daemon daemon({{"--allow-origin", "https://app.example", "--allow-host", "hdof.example"},
                 R"({"mode": "postprocess"})",
                 {}});
  EXPECT_EQ(httpRequest(daemon.port(), "GET", "/healthz", {"Host: hdof.example"}).status, 200);
  EXPECT_EQ(httpRequest(daemon.port(), "GET", "/healthz", {"Host: evil.example"}).status, 403);
  RawConnection listed(daemon.port());
  ASSERT_EQ(listed.upgrade("/session",
                           {"Sec-WebSocket-Protocol: hdof.v1", "Origin: https://app.example"}),
            101);
  ASSERT_TRUE(listed.sendText(helloMessage(kWidth, kHeight)));
  EXPECT_NE(listed.receiveSome(4096).find("\"welcome\""), std::string::npos) << daemon.log();
}

// 4. HEAD answers what GET would without the body; other methods are 405; every response says
//    nosniff and carries the content security policy.
TEST(Hardening, HeadOtherMethodsAndSecurityHeaders) {
  Daemon daemon({{}, R"({"mode": "postprocess"})", {}});
  for (const char* path : {"/healthz", "/metrics", "/", "/app.js"}) {
    HttpExchange get = httpRequest(daemon.port(), "GET", path);
    HttpExchange head = httpRequest(daemon.port(), "HEAD", path);
    EXPECT_EQ(get.status, 200) << path;
    EXPECT_EQ(head.status, 200) << path;
    EXPECT_TRUE(head.body.empty()) << path;
    EXPECT_FALSE(get.body.empty()) << path;
    EXPECT_EQ(headerOf(head, "content-type"), headerOf(get, "content-type")) << path;
    EXPECT_EQ(headerOf(get, "x-content-type-options"), "nosniff") << path;
    EXPECT_NE(headerOf(get, "content-security-policy").find("default-src 'self'"),
              std::string::npos)
        << path;
  }
  for (const char* method : {"POST", "PUT", "DELETE", "OPTIONS", "PATCH"}) {
    HttpExchange response = httpRequest(daemon.port(), method, "/healthz", {"Content-Length: 0"});
    EXPECT_EQ(response.status, 405) << method;
    EXPECT_EQ(headerOf(response, "allow"), "get, head") << method;
  }
  HttpExchange missing = httpRequest(daemon.port(), "GET", "/no-such-file");
  EXPECT_EQ(missing.status, 404);
  EXPECT_EQ(headerOf(missing, "x-content-type-options"), "nosniff");
}

// 5. Symlinks in the web root that lead out of it are not followed; those inside it are.
TEST(Hardening, SymlinksOutOfTheWebRootAreNotServed) {
  auto root = emptyDir("webroot");
  auto outside = emptyDir("outside");
  std::ofstream(root / "index.html") << "<p>inside</p>";
  std::ofstream(outside / "secret.txt") << "outside the web root";
  std::filesystem::create_symlink(outside / "secret.txt", root / "leak.txt");
  std::filesystem::create_directory_symlink(outside, root / "elsewhere");
  std::filesystem::create_symlink(root / "index.html", root / "alias.html");
  std::ofstream(root / ".hidden") << "dot file";
  Daemon daemon({{"--web-root", root.string()}, R"({"mode": "postprocess"})", {}});
  EXPECT_EQ(httpGet(daemon.port(), "/").status, 200);
  EXPECT_EQ(httpGet(daemon.port(), "/alias.html").body, "<p>inside</p>");
  for (const char* path : {"/leak.txt", "/elsewhere/secret.txt", "/elsewhere/", "/.hidden",
                           "/../outside/secret.txt", "/%2e%2e/secret.txt"}) {
    HttpResponse response = httpGet(daemon.port(), path);
    EXPECT_NE(response.status, 200) << path;
    EXPECT_EQ(response.body.find("outside the web root"), std::string::npos) << path;
  }
}

// 6. /healthz fails (503) once the render thread has died or stalled or the device is lost, and
//    new sessions are turned away (busy, 1013) instead of waiting for frames that never come.
void expectUnhealthy(Daemon& daemon, const std::string& field, const std::string& value) {
  nlohmann::json health;
  bool failing = eventually([&] {
    HttpResponse response = httpGet(daemon.port(), "/healthz");
    health = nlohmann::json::parse(response.body, nullptr, false);
    return response.status == 503;
  });
  ASSERT_TRUE(failing) << daemon.log();
  EXPECT_EQ(health.value("status", ""), "failing") << health.dump();
  EXPECT_EQ(health.value(field, ""), value) << health.dump();
  EXPECT_FALSE(health.value("reason", "").empty()) << health.dump();
  EXPECT_EQ(metricValue(daemon.port(), "hdof_healthy"), 0.0);
  auto late = connectSession(daemon.port());
  late->sendText(helloMessage(kWidth, kHeight));
  EXPECT_EQ(nextText(*late).value("code", ""), "busy");
}

TEST(Hardening, HealthzFailsWhenTheRenderThreadDies) {
  Daemon daemon({{}, R"({"mode": "postprocess"})", {{"HDOF_FAULT", "render-thread-exit"}}});
  HttpResponse before = httpGet(daemon.port(), "/healthz");
  EXPECT_EQ(before.status, 200) << before.body;
  EXPECT_EQ(metricValue(daemon.port(), "hdof_healthy"), 1.0);
  auto client = connectSession(daemon.port());
  helloAndWelcome(*client, kWidth, kHeight);  // its first frame is due: the thread fails
  EXPECT_EQ(closeCode(*client), 1011);
  expectUnhealthy(daemon, "render_thread", "stopped");
  EXPECT_EQ(daemon.stop(), 0) << daemon.log();
}

TEST(Hardening, HealthzFailsWhenTheRenderThreadStalls) {
  Daemon daemon(
      {{}, R"({"mode": "postprocess", "render_stall_s": 1})", {{"HDOF_FAULT", "render-stall"}}});
  auto client = connectSession(daemon.port());
  helloAndWelcome(*client, kWidth, kHeight);  // its first frame never finishes
  expectUnhealthy(daemon, "render_thread", "stalled");
  EXPECT_EQ(daemon.stop(), 0) << daemon.log();
}

TEST(Hardening, HealthzFailsWhenTheDeviceIsLost) {
  Daemon daemon({{}, R"({"mode": "postprocess"})", {{"HDOF_FAULT", "device-lost"}}});
  auto client = connectSession(daemon.port());
  helloAndWelcome(*client, kWidth, kHeight);  // its first frame finds the device lost
  EXPECT_EQ(closeCode(*client), 1011);
  expectUnhealthy(daemon, "device_state", "lost");
  EXPECT_EQ(daemon.stop(), 0) << daemon.log();
}

// 7. SIGTERM while the daemon is still starting (scene, BVH, device) stops it at once.
TEST(Hardening, ASignalDuringStartUpStopsTheDaemon) {
  DaemonOptions options{{}, "", {{"HDOF_FAULT", "slow-start"}}};
  options.waitUntilListening = false;
  Daemon daemon(options);
  ASSERT_TRUE(eventually([&] { return daemon.log().find("event=fault") != std::string::npos; }))
      << daemon.log();
  // Without a signal thread yet, the daemon would finish its minute of start-up first and
  // Daemon::stop() would kill it (137) after 30 s.
  EXPECT_EQ(daemon.stop(), 0) << daemon.log();
  EXPECT_NE(daemon.log().find("during=start-up"), std::string::npos) << daemon.log();
}

// 8. A scene whose path is not UTF-8 (glTF names cannot be: the loader rejects them) is named in
//    every welcome, with U+FFFD for the bad bytes.
TEST(Hardening, ASceneNameThatIsNotUtf8) {
  auto dir = emptyDir("scene");
  const float positions[9] = {-5, -5, -2, 5, -5, -2, 0, 5, -2};
  std::string buffer(reinterpret_cast<const char*>(positions), sizeof(positions));
  buffer += std::string("\x00\x01\x02\x00", 4);
  std::ofstream(dir / "tri.bin", std::ios::binary) << buffer;
  std::string scene = (dir / "sc\xe9ne.gltf").string();
  std::ofstream(scene) << R"({"asset": {"version": "2.0"}, "scene": 0,
    "scenes": [{"nodes": [0, 1]}],
    "nodes": [{"name": "wall", "mesh": 0}, {"name": "view", "camera": 0, "translation": [0, 0, 5]}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
       "min": [-5, -5, -2], "max": [5, 5, -2]},
      {"bufferView": 1, "componentType": 5121, "count": 3, "type": "SCALAR"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                    {"buffer": 0, "byteOffset": 36, "byteLength": 3}],
    "buffers": [{"uri": "tri.bin", "byteLength": 40}]})";
  Daemon daemon({{"--scene", scene}, R"({"mode": "postprocess"})", {}});
  for (int i = 0; i < 2; ++i) {
    auto client = connectSession(daemon.port());
    nlohmann::json welcome = helloAndWelcome(*client, kWidth, kHeight);
    std::string name = welcome["scene"].value("name", "");
    EXPECT_NE(name.find("sc\xef\xbf\xbdne.gltf"), std::string::npos) << name;
    EXPECT_TRUE(nextFrame(*client)) << daemon.log();
  }
  EXPECT_EQ(daemon.stop(), 0) << daemon.log();
}

}  // namespace
}  // namespace hdof::test
