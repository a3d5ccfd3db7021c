// hdof serve end to end: the real daemon on a free port, a real WebSocket client. Small viewports
// and builtin:dof keep it quick; no assert depends on timing.
#include "daemon.h"

#include "encode/jpeg.h"
#include "net/message_codec.h"
#include "net/session_state.h"
#include "render/focus_pick.h"
#include "scene/bvh.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <mutex>
#include <thread>

namespace hdof::test {
namespace {

constexpr uint32_t kWidth = 96, kHeight = 64;

// A daemon whose sessions start in `mode` (postprocess: one cheap frame per change).
DaemonOptions withConfig(const std::string& mode, const std::string& more = "") {
  return {{}, R"({"mode": ")" + mode + "\"" + (more.empty() ? "" : ", " + more) + "}", {}};
}

// A session of kInteractiveWidth x kInteractiveHeight in `mode`, on a daemon whose target_fps
// (240) no frame here holds, so that a moving frame renders smaller: its welcome and its first
// frame (acked).
constexpr uint32_t kInteractiveWidth = 160, kInteractiveHeight = 96;
struct InteractiveSession {
  explicit InteractiveSession(const std::string& mode)
      : daemon(withConfig(mode, R"("target_fps": 240, "still_after_ms": 300,
                                   "accumulation_frames": 1)")),
        client(connectSession(daemon.port())),
        welcome(helloAndWelcome(*client, kInteractiveWidth, kInteractiveHeight)),
        first(nextFrame(*client)) {
    if (first) ack(*client, first->header.frame);
  }
  Daemon daemon;
  std::unique_ptr<net::WsClient> client;
  nlohmann::json welcome;
  std::optional<Frame> first;
};

nlohmann::json cameraMessage(const nlohmann::json& welcome, uint32_t seq, float dx) {
  nlohmann::json camera = welcome["camera"];
  camera["seq"] = seq;
  camera["position"][0] = camera["position"][0].get<float>() + dx;
  camera["target"][0] = camera["target"][0].get<float>() + dx;
  return camera;
}

double meanAbsoluteDifference(const ImageRgba8& a, const ImageRgba8& b) {
  if (a.width != b.width || a.height != b.height) {
    ADD_FAILURE() << "images of different sizes: " << a.width << "x" << a.height << " and "
                  << b.width << "x" << b.height;
    return 0.0;
  }
  double sum = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) sum += std::abs(int(a.pixels[i]) - int(b.pixels[i]));
  return sum / double(a.pixels.size());
}

// Frames until one that applies input `seq`, acking each.
std::optional<Frame> frameApplying(net::WsClient& client, uint32_t seq) {
  for (;;) {
    std::optional<Frame> frame = nextFrame(client);
    if (!frame) return frame;
    ack(client, frame->header.frame);
    if (frame->header.seq == seq) return frame;
  }
}

TEST(Serve, HelloGetsWelcomeAndAJpegFrameOfTheViewport) {
  Daemon daemon(withConfig("postprocess"));
  auto client = connectSession(daemon.port());
  nlohmann::json welcome = helloAndWelcome(*client, kWidth, kHeight);
  EXPECT_EQ(welcome["protocol"], 1);
  EXPECT_FALSE(welcome["session"].get<std::string>().empty());
  EXPECT_EQ(welcome["limits"]["max_unacked_frames"], 2);
  EXPECT_EQ(welcome["modes"], nlohmann::json({"pinhole", "postprocess", "raytrace", "hybrid"}));
  EXPECT_EQ(welcome["views"], nlohmann::json(debugViewList()));
  EXPECT_EQ(welcome["scene"]["name"], "builtin:dof");
  EXPECT_EQ(welcome["camera"]["type"], "camera");
  EXPECT_GT(welcome["lens"]["focus_distance"].get<double>(), 0.0);
  // The starting lens keeps the scene camera's framing on a full-frame sensor at this viewport:
  // 2 atan(extent / 2f) of the lens is the camera's field of view.
  EXPECT_EQ(welcome["lens"]["sensor_width_mm"], 36.0);
  EXPECT_EQ(welcome["lens"]["sensor_height_mm"], 24.0);
  double cameraFov = welcome["scene"]["cameras"][0]["fov_y_deg"];
  EXPECT_NEAR(welcome["fov_y_deg"].get<double>(), cameraFov, 1e-3);
  double extentY = 36.0 * kHeight / kWidth;  // 96x64 is 3:2, the sensor's aspect
  EXPECT_NEAR(2.0 * std::atan(extentY / (2.0 * welcome["lens"]["focal_length_mm"].get<double>())),
              cameraFov * M_PI / 180.0, 1e-5);

  std::optional<Frame> frame = nextFrame(*client);
  ASSERT_TRUE(frame) << daemon.log();
  EXPECT_EQ(frame->header.frame, 1u);
  EXPECT_EQ(frame->header.width, kWidth);
  EXPECT_EQ(frame->header.height, kHeight);
  ImageRgba8 image = decodeJpeg(frame->jpeg);
  EXPECT_EQ(image.width, kWidth);
  EXPECT_EQ(image.height, kHeight);
  for (const char* field :
       {"frame", "mode", "passes_ms", "gpu_ms", "render_ms", "encode_ms", "bytes"})
    EXPECT_TRUE(frame->stats.contains(field)) << field << " in " << frame->stats.dump();
  EXPECT_EQ(frame->stats["mode"], "postprocess");
  EXPECT_EQ(frame->stats["bytes"], frame->jpeg.size());
  EXPECT_TRUE(frame->stats["passes_ms"].contains("gbuffer"));
  EXPECT_NEAR(frame->stats["fov_y_deg"].get<double>(), cameraFov, 1e-3);
  // Every pipeline ran once before the daemon listened.
  std::string log = daemon.log();
  size_t warming = log.find("event=pipelines_warming");
  size_t ready = log.find("event=pipelines_ready");
  ASSERT_NE(ready, std::string::npos) << log;
  EXPECT_LT(warming, ready) << "said before it starts: " << log;
  EXPECT_LT(ready, log.find("event=listening")) << log;
}

TEST(Serve, ALongerLensNarrowsTheFieldOfViewAndASensorWidensIt) {
  Daemon daemon(withConfig("pinhole"));
  auto client = connectSession(daemon.port());
  nlohmann::json welcome = helloAndWelcome(*client, kWidth, kHeight);
  nlohmann::json lens = welcome["lens"];
  // The stats of the first frame that applies the lens with these fields changed.
  auto statsWith = [&](uint32_t seq, const nlohmann::json& fields) {
    lens.update(fields);
    lens["seq"] = seq;
    client->sendText(lens.dump());
    std::optional<Frame> frame = frameApplying(*client, seq);
    EXPECT_TRUE(frame) << daemon.log();
    return frame ? frame->stats : nlohmann::json::object();
  };
  // 100 mm on full frame at 3:2: 2 atan(18 / 100) = 20.408 degrees across, 2 atan(12 / 100) =
  // 13.686 up.
  nlohmann::json tele = statsWith(1, {{"focal_length_mm", 100}});
  EXPECT_NEAR(tele.value("fov_x_deg", 0.0), 20.408, 1e-3);
  EXPECT_NEAR(tele.value("fov_y_deg", 0.0), 13.686, 1e-3);
  // A 72 x 48 mm sensor behind the same lens sees twice the tangent: 2 atan(0.36) = 39.598.
  nlohmann::json wide = statsWith(2, {{"sensor_width_mm", 72}, {"sensor_height_mm", 48}});
  EXPECT_NEAR(wide.value("fov_x_deg", 0.0), 39.598, 1e-3);
}

TEST(Serve, CameraMoveGivesADifferentFrameWithItsSeq) {
  Daemon daemon(withConfig("postprocess"));
  auto client = connectSession(daemon.port());
  nlohmann::json welcome = helloAndWelcome(*client, kWidth, kHeight);
  std::optional<Frame> first = nextFrame(*client);
  ASSERT_TRUE(first) << daemon.log();
  ack(*client, first->header.frame);

  client->sendText(cameraMessage(welcome, 7, 0.5f).dump());
  std::optional<Frame> moved = frameApplying(*client, 7);
  ASSERT_TRUE(moved) << daemon.log();
  EXPECT_TRUE(moved->stats.contains("input_to_send_ms")) << moved->stats.dump();
  // A moving frame may render smaller (the interactive scale); the view's resting frame that
  // follows is full size.
  while (moved->header.width != kWidth) {
    moved = nextFrame(*client);
    ASSERT_TRUE(moved) << daemon.log();
    ack(*client, moved->header.frame);
  }
  EXPECT_EQ(moved->header.seq, 7u);
  EXPECT_GT(meanAbsoluteDifference(decodeJpeg(first->jpeg), decodeJpeg(moved->jpeg)), 1.0);
}

TEST(Serve, FocusAtFocusesOnTheDepthUnderThePixel) {
  Daemon daemon(withConfig("postprocess"));
  auto client = connectSession(daemon.port());
  nlohmann::json welcome = helloAndWelcome(*client, kWidth, kHeight);
  nlohmann::json camera = cameraMessage(welcome, 1, 0.0f);
  client->sendText(camera.dump());

  // Two pixels whose surfaces lie at clearly different depths, found as the daemon would.
  Scene scene = loadScene("builtin:dof");
  Bvh bvh = buildBvh(scene.vertices, scene.indices);
  net::CameraMessage message;
  for (int i = 0; i < 3; ++i) {
    message.position[i] = camera["position"][i];
    message.target[i] = camera["target"][i];
    message.up[i] = camera["up"][i];
  }
  Camera view = net::cameraOf(message, Camera::fromScene(scene.cameras.front()));
  Lens lens = net::lensOf(std::get<net::LensMessage>(
      *net::parseClientMessage(welcome["lens"].dump(), net::Limits{}).message));
  std::vector<std::pair<glm::vec2, float>> picks;
  for (uint32_t y = 4; y < kHeight; y += 8)
    for (uint32_t x = 4; x < kWidth; x += 8)
      if (auto depth = depthUnderPixel(bvh, view, lens, kWidth, kHeight, float(x), float(y)))
        if (picks.empty() || std::abs(*depth - picks.front().second) > 0.3f * picks.front().second)
          if (picks.size() < 2) picks.push_back({glm::vec2(x, y), *depth});
  ASSERT_EQ(picks.size(), 2u);

  uint32_t seq = 2;
  for (const auto& [pixel, depth] : picks) {
    client->sendText(
        nlohmann::json{{"type", "focus_at"}, {"seq", seq}, {"x", pixel.x}, {"y", pixel.y}}.dump());
    std::optional<Frame> frame = frameApplying(*client, seq++);
    ASSERT_TRUE(frame) << daemon.log();
    EXPECT_NEAR(frame->stats["focus_distance"].get<double>(), depth, 1e-3 * depth)
        << "pixel " << pixel.x << "," << pixel.y;
    // A pick of the same pixel answers with the same depth and the point it is at.
    client->sendText(
        nlohmann::json{{"type", "pick"}, {"id", seq}, {"x", pixel.x}, {"y", pixel.y}}.dump());
    nlohmann::json picked = nextText(*client);
    ASSERT_EQ(picked.value("type", ""), "picked") << picked.dump();
    EXPECT_EQ(picked["id"], seq);
    ASSERT_EQ(picked["hit"], true) << picked.dump();
    EXPECT_NEAR(picked["depth"].get<double>(), depth, 1e-3 * depth);
    glm::vec3 point(picked["point"][0], picked["point"][1], picked["point"][2]);
    EXPECT_NEAR(glm::length(point - view.position), picked["distance"].get<double>(), 1e-3 * depth);
    EXPECT_NEAR(glm::dot(point - view.position, view.forward), depth, 1e-3 * depth);
  }
}

TEST(Serve, AcksGateFrames) {
  // raytrace keeps rendering while it accumulates: without acks only 2 frames may come.
  Daemon daemon(withConfig("raytrace", R"("accumulation_frames": 1000)"));
  auto client = connectSession(daemon.port());
  helloAndWelcome(*client, 64, 48);
  ASSERT_TRUE(nextFrame(*client)) << daemon.log();
  std::optional<Frame> second = nextFrame(*client);
  ASSERT_TRUE(second) << daemon.log();
  EXPECT_FALSE(nextFrame(*client, 3s)) << "a third frame without an ack";
  ack(*client, second->header.frame);
  std::optional<Frame> third = nextFrame(*client);
  ASSERT_TRUE(third) << daemon.log();
  EXPECT_EQ(third->header.frame, 3u);
  EXPECT_GT(third->stats["accumulated_frames"].get<int>(), 2);
}

// The daemon times the steps of one frame in a few (timestamps cost a software device a few
// percent of a frame); every frame's stats carry the latest timed frame's.
TEST(Serve, EveryFrameCarriesStepTimesThoughFewAreTimed) {
  Daemon daemon(withConfig("raytrace", R"("accumulation_frames": 1000)"));
  auto client = connectSession(daemon.port());
  helloAndWelcome(*client, 64, 48);
  for (int i = 0; i < 12; ++i) {
    std::optional<Frame> frame = nextFrame(*client);
    ASSERT_TRUE(frame) << daemon.log();
    ack(*client, frame->header.frame);
    EXPECT_GT(frame->stats["passes_ms"].value("tonemap", 0.0), 0.0) << frame->stats.dump();
    EXPECT_GT(frame->stats["gpu_ms"].get<double>(), 0.0) << frame->stats.dump();
  }
  double rendered = metricValue(daemon.port(), "hdof_frames_rendered_total");
  double timed = metricValue(daemon.port(), "hdof_pass_seconds_count{pass=\"tonemap\"}");
  EXPECT_GE(timed, 1.0);
  EXPECT_LT(timed, rendered / 2.0) << rendered << " frames rendered";
}

TEST(Serve, LowerQualityWhileMovingThenOneStillFrameThenIdle) {
  Daemon daemon(
      // accumulation_frames 1: no anti-aliasing frames after the still one.
      withConfig("postprocess", R"("jpeg_quality_moving": 30, "jpeg_quality_still": 95,
                                   "still_after_ms": 200, "accumulation_frames": 1)"));
  auto client = connectSession(daemon.port());
  nlohmann::json welcome = helloAndWelcome(*client, kWidth, kHeight);
  std::optional<Frame> first = nextFrame(*client);
  ASSERT_TRUE(first) << daemon.log();
  ack(*client, first->header.frame);
  EXPECT_EQ(first->stats["jpeg_quality"], 95);

  client->sendText(cameraMessage(welcome, 1, 0.2f).dump());
  std::optional<Frame> moving = frameApplying(*client, 1);
  ASSERT_TRUE(moving) << daemon.log();
  EXPECT_EQ(moving->stats["jpeg_quality"], 30);
  std::optional<Frame> still = nextFrame(*client);
  ASSERT_TRUE(still) << daemon.log();
  ack(*client, still->header.frame);
  EXPECT_EQ(still->stats["jpeg_quality"], 95);
  EXPECT_EQ(still->header.seq, 1u);
  EXPECT_FALSE(nextFrame(*client, 1500ms)) << "frames for a still, converged view";
}

// Interactive resolution: a moving view renders smaller when its frames take longer than
// 1 / target_fps, says so in render_scale, and a resting view is full size again.
TEST(Serve, AMovingViewRendersSmallerToHoldTargetFpsAndFullSizeAtRest) {
  InteractiveSession s("hybrid");
  ASSERT_TRUE(s.first) << s.daemon.log();
  EXPECT_EQ(s.first->header.width, kInteractiveWidth);
  EXPECT_EQ(s.first->stats["render_scale"], 1.0);

  // The first moving frame teaches the daemon what a pixel costs; the next ones use it.
  s.client->sendText(cameraMessage(s.welcome, 1, 0.05f).dump());
  std::optional<Frame> moving = frameApplying(*s.client, 1);
  ASSERT_TRUE(moving) << s.daemon.log();
  s.client->sendText(cameraMessage(s.welcome, 2, 0.10f).dump());
  std::optional<Frame> scaled = frameApplying(*s.client, 2);
  ASSERT_TRUE(scaled) << s.daemon.log();
  double scale = scaled->stats["render_scale"].get<double>();
  EXPECT_NEAR(double(scaled->header.width) / kInteractiveWidth, scale, 0.01);
  EXPECT_GE(scale, 0.25);
  std::printf("moving frame %.1f ms at full size, the next at render_scale %.3f (%ux%u)\n",
              moving->stats["render_ms"].get<double>(), scale, scaled->header.width,
              scaled->header.height);
  // 240 frames/s leave 4.2 ms a frame: a moving frame that took longer must have been scaled.
  if (moving->stats["render_ms"].get<double>() > 1000.0 / 240.0) {
    EXPECT_LT(scale, 1.0) << "the moving frame took " << moving->stats["render_ms"] << " ms";
  }

  // The move ends where the view began: after smaller moving frames, the full-size frame at rest
  // is that view's own, drawn afresh, not their history. (Where moving frames are fast enough
  // to render at full size, the resting frame goes on with their history of the same view.)
  s.client->sendText(cameraMessage(s.welcome, 3, 0.0f).dump());
  std::optional<Frame> still;
  double movingScale = scale;  // the scale of the last moving frame
  // Moving frames until the view has rested still_after_ms, then the resting one.
  for (int i = 0; i < 1000; ++i) {
    still = nextFrame(*s.client);
    ASSERT_TRUE(still) << s.daemon.log();
    ack(*s.client, still->header.frame);
    if (still->header.seq != 3u) continue;
    if (!still->stats["moving"].get<bool>()) break;
    movingScale = still->stats["render_scale"].get<double>();
  }
  EXPECT_FALSE(still->stats["moving"].get<bool>());
  EXPECT_EQ(still->header.width, kInteractiveWidth) << "full size at rest";
  EXPECT_EQ(still->header.height, kInteractiveHeight);
  if (movingScale < 1.0) {
    EXPECT_LT(meanAbsoluteDifference(decodeJpeg(s.first->jpeg), decodeJpeg(still->jpeg)), 2.0);
  }
}

// A focus change on a resting view keeps its size: the raster stands there and only the depth
// of field is redone, where a smaller frame would draw it again (and show the focus blurred).
TEST(Serve, AFocusChangeOnARestingViewKeepsItsSize) {
  InteractiveSession s("postprocess");
  ASSERT_TRUE(s.first) << s.daemon.log();
  nlohmann::json lens = s.welcome["lens"];
  lens["seq"] = 1;
  lens["focus_distance"] = lens["focus_distance"].get<double>() * 0.8;
  s.client->sendText(lens.dump());
  std::optional<Frame> pulled = frameApplying(*s.client, 1);
  ASSERT_TRUE(pulled) << s.daemon.log();
  EXPECT_TRUE(pulled->stats["moving"].get<bool>());
  EXPECT_EQ(pulled->stats["render_scale"], 1.0)
      << "the first frame took " << s.first->stats["render_ms"] << " ms";
  EXPECT_EQ(pulled->header.width, kInteractiveWidth);
  EXPECT_GT(meanAbsoluteDifference(decodeJpeg(s.first->jpeg), decodeJpeg(pulled->jpeg)), 0.1)
      << "the focus moved";
}

// A frame that refines a resting view (an accumulation) waits while another session moves, whose
// frames would otherwise wait for it; the refinement goes on once that view rests too. /metrics
// counts the moving session alone as interactive meanwhile, and none once both refine.
TEST(Serve, RefiningFramesWaitWhileAnotherSessionMoves) {
  // still_after_ms: the moving session stays interactive between its inputs, however slowly
  // this machine serves them.
  Daemon daemon(withConfig("raytrace", R"("accumulation_frames": 100000, "still_after_ms": 1000)"));
  using Clock = std::chrono::steady_clock;
  auto resting = connectSession(daemon.port());
  helloAndWelcome(*resting, kWidth, kHeight);
  std::mutex mutex;
  std::vector<Clock::time_point> refined;  // when each of the resting session's frames came
  std::atomic<bool> done = false;
  std::thread reader([&] {
    while (!done) {
      std::optional<Frame> frame = nextFrame(*resting, 100ms);
      if (!frame) continue;
      ack(*resting, frame->header.frame);
      std::lock_guard lock(mutex);
      refined.push_back(Clock::now());
    }
  });
  auto framesBetween = [&](Clock::time_point from, Clock::time_point to) {
    std::lock_guard lock(mutex);
    return std::count_if(refined.begin(), refined.end(),
                         [&](Clock::time_point t) { return t > from && t < to; });
  };

  auto moving = connectSession(daemon.port());
  nlohmann::json welcome = helloAndWelcome(*moving, kWidth, kHeight);
  std::optional<Frame> first = nextFrame(*moving);
  ASSERT_TRUE(first) << daemon.log();
  ack(*moving, first->header.frame);
  // One of the resting session's frames may be under way when the move starts, and reach the
  // client a little later.
  Clock::time_point moveStart = Clock::now();
  uint32_t seq = 0;
  int movingFrames = 0;
  double interactiveWhileMoving = -1.0;
  while (Clock::now() < moveStart + 2s) {
    ++seq;
    moving->sendText(cameraMessage(welcome, seq, 0.01f * float(seq % 20)).dump());
    std::optional<Frame> frame = frameApplying(*moving, seq);
    ASSERT_TRUE(frame) << daemon.log();
    if (++movingFrames == 3)
      interactiveWhileMoving = metricValue(daemon.port(), "hdof_sessions_interactive");
  }
  Clock::time_point moveEnd = Clock::now();
  long during = framesBetween(moveStart + 500ms, moveEnd);
  // The moving view's frames go on (it accumulates too) until still_after_ms after its last
  // input, then one at rest; then the resting view refines again.
  std::optional<Frame> still;
  do {
    still = nextFrame(*moving);
    ASSERT_TRUE(still) << daemon.log();
    ack(*moving, still->header.frame);
  } while (still->stats["moving"].get<bool>());
  Clock::time_point rested = Clock::now();
  while (framesBetween(rested, Clock::now()) < 3 && Clock::now() < rested + kTimeout)
    std::this_thread::sleep_for(50ms);
  long after = framesBetween(rested, Clock::now());
  done = true;
  reader.join();
  EXPECT_GE(movingFrames, 2);
  EXPECT_LE(during, 1) << "refining frames while the other session moved (" << movingFrames
                       << " moving frames)";
  EXPECT_GE(after, 3) << "the resting view refines once no view moves";
  EXPECT_EQ(interactiveWhileMoving, 1.0) << "the moving session alone";
  EXPECT_EQ(metricValue(daemon.port(), "hdof_sessions_interactive"), 0.0) << "both refine";
}

TEST(Serve, BadInputGetsAnErrorAndTheSessionGoesOn) {
  Daemon daemon(withConfig("postprocess", R"("max_rays_per_pixel": 8)"));
  auto client = connectSession(daemon.port());
  nlohmann::json welcome = helloAndWelcome(*client, kWidth, kHeight);
  nlohmann::json camera = cameraMessage(welcome, 1, 0.0f);
  auto withField = [&](const std::string& field, nlohmann::json value) {
    nlohmann::json message = camera;
    message[field] = value;
    return message.dump();
  };
  struct Case {
    std::string message, code, field;
  } cases[] = {
      {"not json", "bad_json", ""},
      {"[1, 2]", "bad_json", ""},
      {R"({"type": "warp"})", "unknown_type", "type"},
      {R"({"seq": 1})", "bad_field", "type"},
      {withField("position", "here"), "bad_field", "position"},
      {withField("fov_y_deg", 40), "bad_field", "fov_y_deg"},  // the lens makes it
      // JSON has no infinity: a number too large for a double is not JSON the parser takes.
      {R"({"type":"camera","seq":1,"position":[0,0,1e999],"target":[0,0,0]})", "bad_json", ""},
      {withField("zoom", 2), "bad_field", "zoom"},
      {withField("seq", -1), "out_of_range", "seq"},
      {withField("seq", 1.5), "bad_field", "seq"},
      {R"({"type":"lens","seq":1,"focal_length_mm":50,"f_number":-1,"focus_distance":2})",
       "out_of_range", "f_number"},
      {R"({"type":"lens","seq":1,"focal_length_mm":50,"f_number":2,"focus_distance":2,"sensor_width_mm":400,"sensor_height_mm":24})",
       "out_of_range", "sensor_width_mm"},
      {R"({"type":"focus_at","seq":1,"x":5000,"y":1})", "out_of_range", "x"},
      {R"({"type":"pick","id":1,"x":1,"y":5000})", "out_of_range", "y"},
      {R"({"type":"mode","seq":1,"mode":"blurry"})", "out_of_range", "mode"},
      {R"({"type":"settings","rays_per_pixel":9})", "out_of_range", "rays_per_pixel"},
      {R"({"type":"ack","frame":99999})", "out_of_range", "frame"},
      {helloMessage(kWidth, kHeight), "not_allowed", "type"},
  };
  for (const Case& c : cases) {
    client->sendText(c.message);
    nlohmann::json error = nextText(*client);
    ASSERT_EQ(error.value("type", ""), "error") << c.message << "\n" << daemon.log();
    EXPECT_EQ(error["code"], c.code) << c.message << ": " << error.dump();
    EXPECT_EQ(error.value("field", ""), c.field) << c.message << ": " << error.dump();
    EXPECT_FALSE(error["message"].get<std::string>().empty());
  }
  client->sendText(cameraMessage(welcome, 9, 0.1f).dump());
  EXPECT_TRUE(frameApplying(*client, 9)) << daemon.log();
}

TEST(Serve, ProtocolViolationsCloseWithTheirCode) {
  Daemon daemon(withConfig("postprocess", R"("max_message_bytes": 1024)"));
  {
    auto client = connectSession(daemon.port());
    client->sendText(R"({"type":"ack","frame":1})");
    EXPECT_EQ(closeCode(*client), 1002) << "no hello first";
  }
  {
    auto client = connectSession(daemon.port());
    helloAndWelcome(*client, kWidth, kHeight);
    client->sendBinary({1, 2, 3});
    EXPECT_EQ(closeCode(*client), 1002) << "binary from the client";
  }
  {
    auto client = connectSession(daemon.port());
    helloAndWelcome(*client, kWidth, kHeight);
    client->sendText(R"({"type":"settings","pad":")" + std::string(4000, 'x') + "\"}");
    std::string reason;
    EXPECT_EQ(closeCode(*client, &reason), 1009) << "oversize";
    EXPECT_NE(reason.find("1024"), std::string::npos) << reason;
  }
  // The daemon is still there for the next client.
  auto client = connectSession(daemon.port());
  helloAndWelcome(*client, kWidth, kHeight);
  EXPECT_TRUE(nextFrame(*client)) << daemon.log();
}

TEST(Serve, TokenIsEnforced) {
  Daemon daemon({{"--token", "s3cret"}, "", {}});
  for (std::string token : {"", "wrong"}) {
    auto client = connectSession(daemon.port());
    client->sendText(helloMessage(kWidth, kHeight, token));
    nlohmann::json error = nextText(*client);
    EXPECT_EQ(error.value("code", ""), "not_allowed") << error.dump();
    EXPECT_EQ(closeCode(*client), 1008) << "token '" << token << "'";
  }
  auto client = connectSession(daemon.port());
  helloAndWelcome(*client, kWidth, kHeight, "s3cret");
}

TEST(Serve, TokenFromTheEnvironment) {
  Daemon daemon({{}, "", {{"HDOF_TOKEN", "from-env"}}});
  auto refused = connectSession(daemon.port());
  refused->sendText(helloMessage(kWidth, kHeight));
  EXPECT_EQ(closeCode(*refused), 1008);
  auto client = connectSession(daemon.port());
  helloAndWelcome(*client, kWidth, kHeight, "from-env");
}

TEST(Serve, OriginNotAllowedCloses1008) {
  Daemon daemon({{"--allow-origin", "http://good.example"}, "", {}});
  auto evil = connectSession(daemon.port(), "evil.example");  // sent as http://evil.example
  EXPECT_EQ(closeCode(*evil), 1008);
  auto good = connectSession(daemon.port(), "good.example");
  helloAndWelcome(*good, kWidth, kHeight);
}

TEST(Serve, TooManySessionsGetBusyAnd1013) {
  Daemon daemon(withConfig("postprocess", R"("max_sessions": 1)"));
  auto first = connectSession(daemon.port());
  helloAndWelcome(*first, kWidth, kHeight);
  auto second = connectSession(daemon.port());
  second->sendText(helloMessage(kWidth, kHeight));
  EXPECT_EQ(nextText(*second).value("code", ""), "busy");
  EXPECT_EQ(rawCloseCode(daemon.port(), {helloMessage(kWidth, kHeight)}), 1013);
  first->close();
  closeCode(*first);
  // The daemon counts the first session out once it has seen the close: try a few times.
  bool welcomed = false;
  for (int attempt = 0; attempt < 50 && !welcomed; ++attempt) {
    auto third = connectSession(daemon.port());
    third->sendText(helloMessage(kWidth, kHeight));
    welcomed = nextText(*third).value("type", "") == "welcome";
    if (!welcomed) std::this_thread::sleep_for(100ms);
  }
  EXPECT_TRUE(welcomed) << daemon.log();
}

TEST(Serve, HealthzMetricsAndTheWebRoot) {
  Daemon daemon(withConfig("postprocess"));
  HttpResponse health = httpGet(daemon.port(), "/healthz");
  EXPECT_EQ(health.status, 200);
  nlohmann::json body = nlohmann::json::parse(health.body, nullptr, false);
  EXPECT_EQ(body.value("status", ""), "ok") << health.body;
  EXPECT_FALSE(body.value("device", "").empty()) << health.body;
  EXPECT_NE(httpGet(daemon.port(), "/").body.find("src=\"app.js\""), std::string::npos);
  EXPECT_EQ(httpGet(daemon.port(), "/app.js").status, 200);
  EXPECT_EQ(httpGet(daemon.port(), "/no-such-file").status, 404);

  auto client = connectSession(daemon.port());
  helloAndWelcome(*client, kWidth, kHeight);
  ASSERT_TRUE(nextFrame(*client)) << daemon.log();
  client->sendText("{");
  nextText(*client);
  std::string metrics = httpGet(daemon.port(), "/metrics").body;
  // A still view may already have refined its first frame with a second one: counts of frames
  // are at least one, and agree with each other.
  auto value = [&](const std::string& sample) {
    size_t at = metrics.find("\n" + sample + " ");
    return at == std::string::npos ? -1.0 : std::stod(metrics.substr(at + sample.size() + 2));
  };
  EXPECT_EQ(value("hdof_sessions"), 1.0) << metrics;
  EXPECT_EQ(value("hdof_errors_total{code=\"bad_json\"}"), 1.0) << metrics;
  double sent = value("hdof_frames_sent_total");
  EXPECT_GE(sent, 1.0) << metrics;
  EXPECT_GE(value("hdof_frames_rendered_total"), sent) << metrics;
  EXPECT_GE(value("hdof_encode_seconds_count"), sent) << metrics;
  EXPECT_GE(value("hdof_pass_seconds_bucket{pass=\"gbuffer\",le=\"+Inf\"}"), 1.0) << metrics;
  EXPECT_NE(metrics.find("# TYPE hdof_frames_dropped_total counter"), std::string::npos) << metrics;
}

TEST(Serve, AVanishingClientFreesItsSession) {
  Daemon daemon(withConfig("raytrace", R"("accumulation_frames": 1000)"));
  {
    auto client = connectSession(daemon.port());
    helloAndWelcome(*client, kWidth, kHeight);
    ASSERT_TRUE(nextFrame(*client)) << daemon.log();
  }  // gone mid-stream, frames still rendering
  bool freed = false;
  for (int i = 0; i < 200 && !freed; ++i) {
    freed = httpGet(daemon.port(), "/metrics").body.find("hdof_sessions 0") != std::string::npos;
    if (!freed) std::this_thread::sleep_for(100ms);
  }
  EXPECT_TRUE(freed) << daemon.log();
  auto client = connectSession(daemon.port());
  helloAndWelcome(*client, kWidth, kHeight);
  EXPECT_TRUE(nextFrame(*client)) << daemon.log();
}

TEST(Serve, ShutdownClosesSessionsWithGoingAway) {
  Daemon daemon(withConfig("postprocess"));
  auto client = connectSession(daemon.port());
  helloAndWelcome(*client, kWidth, kHeight);
  ASSERT_TRUE(nextFrame(*client)) << daemon.log();
  EXPECT_EQ(daemon.stop(), 0) << daemon.log();
  EXPECT_EQ(closeCode(*client), 1001);
  std::string log = daemon.log();
  EXPECT_NE(log.find("event=session_end"), std::string::npos) << log;
  EXPECT_NE(log.find("event=stopped"), std::string::npos) << log;
}

}  // namespace
}  // namespace hdof::test
