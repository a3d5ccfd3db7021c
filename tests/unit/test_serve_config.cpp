// hdof serve's config file and its Prometheus metrics text, without starting anything.
#include "app/cli.h"
#include "app/serve_config.h"
#include "net/metrics.h"

#include <gtest/gtest.h>

namespace hdof {
namespace {

TEST(ServeConfig, KeysOverTheDefaults) {
  ServeConfig c = parseServeConfig(
      R"({"port": 9000, "bind": "0.0.0.0", "max_sessions": 3, "max_width": 800,
          "max_message_bytes": 2048, "max_rays_per_pixel": 4, "rays_per_pixel": 2,
          "mode": "postprocess", "jpeg_quality_moving": 40, "max_fps": 30.5,
          "allowed_origins": ["http://a", "http://b"], "still_after_ms": 0})",
      "test");
  EXPECT_EQ(c.port, 9000u);
  EXPECT_EQ(c.bind, "0.0.0.0");
  EXPECT_EQ(c.maxSessions, 3u);
  EXPECT_EQ(c.limits.maxWidth, 800u);
  EXPECT_EQ(c.limits.maxHeight, 1080u) << "a default";
  EXPECT_EQ(c.limits.maxMessageBytes, 2048u);
  EXPECT_EQ(c.stream.raysPerPixel, 2u);
  EXPECT_EQ(c.mode, "postprocess");
  EXPECT_EQ(c.stream.jpegQualityMoving, 40);
  EXPECT_EQ(c.stream.maxFps, 30.5);
  EXPECT_EQ(c.allowedOrigins.size(), 2u);
  EXPECT_EQ(c.stillAfterMs, 0.0);
}

TEST(ServeConfig, BadConfigNamesTheKey) {
  auto expectError = [](const std::string& text, const std::string& expected) {
    try {
      parseServeConfig(text, "test");
      ADD_FAILURE() << text;
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  expectError("{", "not a JSON object");
  expectError("[]", "not a JSON object");
  expectError(R"({"prot": 1})", "'prot'");
  expectError(R"({"port": 70000})", "'port'");
  expectError(R"({"port": "80"})", "'port'");
  expectError(R"({"max_sessions": 0})", "'max_sessions'");
  expectError(R"({"max_sessions": 2.5})", "'max_sessions'");
  expectError(R"({"max_fps": 0})", "'max_fps'");
  expectError(R"({"allowed_origins": "http://a"})", "'allowed_origins'");
  expectError(R"({"mode": "reference"})", "reference");
  expectError(R"({"max_rays_per_pixel": 2, "rays_per_pixel": 4})", "max_rays_per_pixel");
  expectError(R"({"allowed_hosts": "a"})", "'allowed_hosts'");
  expectError(R"({"allow_insecure_token": 1})", "'allow_insecure_token'");
  expectError(R"({"render_stall_s": 0})", "'render_stall_s'");
}

TEST(ServeConfig, AccessSettings) {
  ServeConfig c = parseServeConfig(
      R"({"allowed_hosts": ["hdof.example"], "render_stall_s": 5, "allow_insecure_token": true})",
      "test");
  EXPECT_EQ(c.allowedHosts, std::vector<std::string>{"hdof.example"});
  EXPECT_EQ(c.renderStallS, 5u);
  EXPECT_TRUE(c.allowInsecureToken);
  auto usageError = [](const ServeConfig& config) {
    try {
      checkServeAccess(config);
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  auto config = [](std::string bind, std::string token, bool allowInsecure = false) {
    ServeConfig c;
    c.bind = std::move(bind);
    c.token = std::move(token);
    c.allowInsecureToken = allowInsecure;
    return c;
  };
  EXPECT_EQ(usageError(config("127.0.0.1", "t")), "") << "a token on loopback";
  EXPECT_NE(usageError(config("127.0.0.1", std::string(257, 'x'))).find("at most 256"),
            std::string::npos)
      << "hello could never carry it";
  EXPECT_EQ(usageError(config("0.0.0.0", "")), "") << "no token";
  EXPECT_NE(usageError(config("0.0.0.0", "t")).find("--allow-insecure-token"), std::string::npos);
  EXPECT_EQ(usageError(config("0.0.0.0", "t", true)), "");
}

TEST(Metrics, PrometheusText) {
  net::Metrics metrics;
  metrics.sessionStarted();
  metrics.frameRendered({{"gbuffer", 2.0}, {"tonemap", 0.1}});
  metrics.frameSent(1000, 0.7, 12.0);
  metrics.frameSent(500, 3.0, std::nullopt);
  metrics.frameRendered({});
  metrics.frameRendered({});
  metrics.frameDropped();
  metrics.sessionTimedOut();
  metrics.error(net::ErrorCode::BadJson);
  metrics.closed(1009);
  EXPECT_EQ(metrics.framesQueued(), 0u) << "3 rendered: 2 sent, 1 dropped";
  std::string text = metrics.prometheusText();
  for (const char* line :
       {"# TYPE hdof_sessions gauge\nhdof_sessions 1\n", "hdof_frames_sent_total 2\n",
        "hdof_bytes_sent_total 1500\n", "hdof_errors_total{code=\"bad_json\"} 1\n",
        "hdof_closes_total{code=\"1009\"} 1\n", "# TYPE hdof_pass_seconds histogram\n",
        "hdof_pass_seconds_bucket{pass=\"gbuffer\",le=\"0.001\"} 0\n",
        "hdof_pass_seconds_bucket{pass=\"gbuffer\",le=\"0.0025\"} 1\n",
        "hdof_pass_seconds_bucket{pass=\"gbuffer\",le=\"+Inf\"} 1\n",
        "hdof_pass_seconds_count{pass=\"gbuffer\"} 1\n",
        "hdof_encode_seconds_bucket{le=\"0.001\"} 1\n", "hdof_encode_seconds_count 2\n",
        "hdof_input_to_send_seconds_count 1\n", "hdof_input_to_send_seconds_sum 0.012\n",
        "hdof_frames_rendered_total 3\n", "# TYPE hdof_frames_queued gauge\nhdof_frames_queued 0\n",
        "hdof_frames_dropped_total 1\n", "hdof_sessions_timed_out_total 1\n"})
    EXPECT_NE(text.find(line), std::string::npos) << line << "\nin\n" << text;
  metrics.sessionEnded();
  EXPECT_EQ(metrics.activeSessions(), 0);
}

}  // namespace
}  // namespace hdof
