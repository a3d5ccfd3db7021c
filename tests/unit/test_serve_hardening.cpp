// The daemon's defences without a network: the Host and Origin checks, close reasons that stay
// UTF-8, a welcome that survives text that is not UTF-8, and the bounded encode stage.
#include "net/access_policy.h"
#include "net/frame_encoder.h"
#include "net/server_messages.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace hdof::net {
namespace {

using Header = std::optional<std::string>;

TEST(AccessPolicy, ParsesAuthorities) {
  auto host = [](const char* text) {
    auto a = parseAuthority(text);
    return a ? a->host + "|" + std::to_string(a->port) : std::string("none");
  };
  EXPECT_EQ(host("LocalHost:8080"), "localhost|8080");
  EXPECT_EQ(host("example.com"), "example.com|0");
  EXPECT_EQ(host("[::1]:9"), "::1|9");
  EXPECT_EQ(host("[::1]"), "::1|0");
  for (const char* bad : {"", ":80", "a:", "a:b", "a:70000", "::1", "[::1", "a b", "a/b", "u@h"})
    EXPECT_EQ(host(bad), "none") << bad;
}

TEST(AccessPolicy, LoopbackNames) {
  for (const char* name :
       {"localhost", "LOCALHOST", "app.localhost", "127.0.0.1", "127.1.2.3", "::1", "localhost."})
    EXPECT_TRUE(isLoopbackHost(name)) << name;
  for (const char* name : {"0.0.0.0", "128.0.0.1", "127.0.0", "127.0.0.1.evil.example",
                           "localhost.evil.example", "evil.example", "1270.0.0.1", ""})
    EXPECT_FALSE(isLoopbackHost(name)) << name;
  EXPECT_TRUE(isLoopbackBind("127.0.0.1"));
  EXPECT_TRUE(isLoopbackBind("lo"));
  EXPECT_FALSE(isLoopbackBind("0.0.0.0"));
  EXPECT_FALSE(isLoopbackBind(""));
}

TEST(AccessPolicy, HostIsCheckedWhenBoundToLoopback) {
  AccessPolicy loopback = AccessPolicy::forServer("127.0.0.1", 8080, {}, {});
  EXPECT_TRUE(loopback.hostAllowed(Header("127.0.0.1:8080")));
  EXPECT_TRUE(loopback.hostAllowed(Header("localhost:8080")));
  EXPECT_TRUE(loopback.hostAllowed(std::nullopt)) << "no Host: not a browser";
  EXPECT_FALSE(loopback.hostAllowed(Header("evil.example:8080"))) << "DNS rebinding";
  EXPECT_FALSE(loopback.hostAllowed(Header("?")));
  AccessPolicy proxied = AccessPolicy::forServer("127.0.0.1", 8080, {}, {"Hdof.Example"});
  EXPECT_TRUE(proxied.hostAllowed(Header("hdof.example")));
  EXPECT_TRUE(proxied.hostAllowed(Header("hdof.example:8443")));
  EXPECT_FALSE(proxied.hostAllowed(Header("evil.example")));
  AccessPolicy everywhere = AccessPolicy::forServer("0.0.0.0", 8080, {}, {});
  EXPECT_TRUE(everywhere.hostAllowed(Header("anything.example")));
}

TEST(AccessPolicy, SameOriginByDefault) {
  AccessPolicy policy = AccessPolicy::forServer("127.0.0.1", 8080, {}, {});
  Header host("127.0.0.1:8080");
  EXPECT_TRUE(policy.originAllowed(Header("http://127.0.0.1:8080"), host));
  EXPECT_TRUE(policy.originAllowed(Header("http://localhost:8080"), host)) << "loopback, our port";
  EXPECT_TRUE(policy.originAllowed(std::nullopt, host)) << "no Origin: a program, not a page";
  EXPECT_FALSE(policy.originAllowed(Header("http://evil.example"), host));
  EXPECT_FALSE(policy.originAllowed(Header("http://localhost:8000"), host)) << "another port";
  EXPECT_FALSE(policy.originAllowed(Header("null"), host));
  EXPECT_FALSE(policy.originAllowed(Header("file://"), host));
  EXPECT_FALSE(policy.originAllowed(Header("ftp://127.0.0.1:8080"), host));
  // Behind a proxy that passes the Host header on: the page's origin is the proxy's.
  AccessPolicy behind = AccessPolicy::forServer("0.0.0.0", 8080, {}, {});
  EXPECT_TRUE(behind.originAllowed(Header("https://hdof.example"), Header("hdof.example")));
  EXPECT_TRUE(
      behind.originAllowed(Header("https://hdof.example:8443"), Header("hdof.example:8443")));
  EXPECT_TRUE(behind.originAllowed(Header("http://hdof.example"), Header("hdof.example:80")));
  EXPECT_FALSE(behind.originAllowed(Header("https://hdof.example:8443"), Header("hdof.example")));
  EXPECT_FALSE(behind.originAllowed(Header("https://evil.example"), Header("hdof.example")));
  EXPECT_FALSE(behind.originAllowed(Header("https://hdof.example"), std::nullopt));
}

TEST(AccessPolicy, AllowedOriginsAreExact) {
  AccessPolicy policy = AccessPolicy::forServer("127.0.0.1", 8080, {"https://app.example"}, {});
  EXPECT_TRUE(policy.originAllowed(Header("https://app.example"), Header("127.0.0.1:8080")));
  EXPECT_FALSE(policy.originAllowed(Header("http://app.example"), Header("127.0.0.1:8080")));
  EXPECT_FALSE(policy.originAllowed(std::nullopt, Header("127.0.0.1:8080")))
      << "with a list, an Origin is required";
}

TEST(ServerMessages, CloseReasonsAreWholeUtf8Characters) {
  std::string euros;
  for (int i = 0; i < 60; ++i) euros += "\xe2\x82\xac";  // 180 bytes of 3-byte characters
  std::string cut = utf8Prefix(euros, 123);
  EXPECT_EQ(cut.size(), 123u) << "41 whole characters";
  EXPECT_EQ(utf8Prefix(euros, 124).size(), 123u) << "never half a character";
  EXPECT_EQ(utf8Prefix("ab\xff"
                       "c\xc3",
                       10),
            "ab?c?")
      << "bad bytes become '?'";
  EXPECT_EQ(utf8Prefix("\xc0\xaf", 10), "??") << "overlong";
  EXPECT_EQ(utf8Prefix("\xed\xa0\x80", 10), "???") << "a surrogate";
  EXPECT_EQ(utf8Prefix("plain", 3), "pla");
}

TEST(ServerMessages, AWelcomeWithNamesThatAreNotUtf8) {
  Welcome welcome;
  welcome.session = "1";
  welcome.sceneName = "/scenes/caf\xe9.gltf";
  SceneCamera camera;
  camera.name = "view \xff\xfe";
  camera.position = {0.0f, 0.0f, 5.0f};
  welcome.cameras.push_back(camera);
  std::string text;
  ASSERT_NO_THROW(text = welcomeMessage(welcome));
  nlohmann::json parsed = nlohmann::json::parse(text, nullptr, false);
  ASSERT_TRUE(parsed.is_object()) << text;
  EXPECT_EQ(parsed["scene"]["name"], "/scenes/caf\xef\xbf\xbd.gltf");
  EXPECT_EQ(parsed["scene"]["cameras"][0]["name"], "view \xef\xbf\xbd\xef\xbf\xbd");
}

// The encoder stand-in: keeps the jobs until the test finishes them.
struct ManualEncoder {
  std::vector<std::function<void(EncodedJpeg)>> jobs;
  FrameEncoder::Encode encode() {
    return [this](ImageRgba8, int, std::function<void(EncodedJpeg)> done) {
      jobs.push_back(std::move(done));
    };
  }
  void finish(size_t job) {
    EncodedJpeg jpeg;
    jpeg.bytes = {1, 2, 3};
    jobs[job](std::move(jpeg));
  }
};

StreamFrame frameNumber(uint32_t number) {
  StreamFrame frame;
  frame.session = 1;
  frame.plan.frame = number;
  frame.image = {4, 4, std::vector<uint8_t>(64)};
  return frame;
}

TEST(FrameEncoder, BoundedQueueDropsTheOldest) {
  ManualEncoder pool;
  std::vector<uint32_t> encoded, dropped;
  FrameEncoder encoder(
      pool.encode(), 1, 2, [&](StreamFrame f) { encoded.push_back(f.plan.frame); },
      [&](StreamFrame f) { dropped.push_back(f.plan.frame); });
  for (uint32_t n = 1; n <= 5; ++n) encoder.submit(frameNumber(n));
  EXPECT_EQ(pool.jobs.size(), 1u) << "one worker: one frame with the encoder";
  EXPECT_EQ(encoder.waiting(), 2u) << "capacity 2";
  EXPECT_EQ(dropped, (std::vector<uint32_t>{2, 3})) << "the oldest waiting ones go";
  pool.finish(0);
  EXPECT_EQ(encoded, std::vector<uint32_t>{1});
  ASSERT_EQ(pool.jobs.size(), 2u) << "the next waiting frame went to the encoder";
  pool.finish(1);
  pool.finish(2);
  EXPECT_EQ(encoded, (std::vector<uint32_t>{1, 4, 5}));
  EXPECT_EQ(encoder.waiting(), 0u);
}

TEST(FrameEncoder, ShutdownDropsWhatWaits) {
  ManualEncoder pool;
  std::vector<uint32_t> encoded, dropped;
  FrameEncoder encoder(
      pool.encode(), 1, 4, [&](StreamFrame f) { encoded.push_back(f.plan.frame); },
      [&](StreamFrame f) { dropped.push_back(f.plan.frame); });
  encoder.submit(frameNumber(1));
  encoder.submit(frameNumber(2));
  encoder.shutdown();
  EXPECT_EQ(dropped, std::vector<uint32_t>{2});
  pool.finish(0);
  EXPECT_EQ(encoded, std::vector<uint32_t>{1}) << "the frame being encoded still comes back";
  EXPECT_EQ(pool.jobs.size(), 1u) << "nothing more handed over";
  encoder.submit(frameNumber(3));
  EXPECT_EQ(dropped, (std::vector<uint32_t>{2, 3}));
}

}  // namespace
}  // namespace hdof::net
