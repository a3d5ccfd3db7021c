// Clients that misbehave: the daemon cuts them off or ignores them, keeps serving a well-behaved
// session alongside, and exits cleanly at the end (exit code 0: in the sanitizer build that
// includes LeakSanitizer's check of everything the faults allocated).
#include "daemon.h"

#include <gtest/gtest.h>

#include <random>
#include <thread>

namespace hdof::test {
namespace {

constexpr uint32_t kWidth = 96, kHeight = 54;

// A daemon with short timeouts, and one well-behaved session on it.
class Faults : public ::testing::Test {
 protected:
  Faults()
      : daemon_({{},
                 R"({"mode": "postprocess", "client_timeout_s": 2, "hello_timeout_s": 2,
                     "max_sessions": 4})",
                 {}}) {
    good_ = connectSession(daemon_.port());
    welcome_ = helloAndWelcome(*good_, kWidth, kHeight);
    std::optional<Frame> first = nextFrame(*good_);
    EXPECT_TRUE(first) << daemon_.log();
    if (first) ack(*good_, first->header.frame);
  }

  // The good session still gets a frame for a new camera input.
  void expectGoodSessionServed() {
    nlohmann::json camera = welcome_["camera"];
    camera["seq"] = ++seq_;
    camera["position"][0] = camera["position"][0].get<double>() + 0.05 * (seq_ % 5);
    good_->sendText(camera.dump());
    for (;;) {
      std::optional<Frame> frame = nextFrame(*good_);
      ASSERT_TRUE(frame) << "the well-behaved session got no frame\n" << daemon_.log();
      ack(*good_, frame->header.frame);
      if (frame->header.seq == seq_) return;
    }
  }

  // Waits until the daemon counts `sessions` open sessions.
  void expectSessionsBecome(double sessions) {
    double now = -1.0;
    for (int i = 0; i < 300 && now != sessions; ++i) {
      now = metricValue(daemon_.port(), "hdof_sessions");
      if (now != sessions) std::this_thread::sleep_for(100ms);
    }
    EXPECT_EQ(now, sessions) << daemon_.log();
  }

  void TearDown() override {
    expectGoodSessionServed();
    good_.reset();
    EXPECT_EQ(daemon_.stop(), 0) << daemon_.log();
  }

  Daemon daemon_;
  std::unique_ptr<net::WsClient> good_;
  nlohmann::json welcome_;
  uint32_t seq_ = 0;
};

TEST_F(Faults, ClientsThatDisconnectMidFrame) {
  for (int i = 0; i < 5; ++i) {
    RawConnection client(daemon_.port());
    ASSERT_TRUE(client.handshake());
    ASSERT_TRUE(client.sendText(helloMessage(kWidth, kHeight)));
    // The welcome, then the first bytes of the first frame (its magic): gone before the rest.
    std::string received;
    while (received.find("HDOF") == std::string::npos) {
      std::string some = client.receiveSome(256);
      ASSERT_FALSE(some.empty()) << "no frame came\n" << daemon_.log();
      received += some;
    }
  }
  expectSessionsBecome(1);
}

TEST_F(Faults, AClientThatSendsHalfAFrameAndStallsIsCutOff) {
  RawConnection beforeHello(daemon_.port()), afterHello(daemon_.port());
  ASSERT_TRUE(beforeHello.handshake());
  ASSERT_TRUE(afterHello.handshake());
  ASSERT_TRUE(afterHello.sendText(helloMessage(kWidth, kHeight)));
  std::string frame =
      maskedTextFrame(R"({"type":"ack","frame":1,"pad":")" + std::string(200, 'x') + "\"}");
  ASSERT_TRUE(beforeHello.sendBytes(frame.substr(0, 40)));
  ASSERT_TRUE(afterHello.sendBytes(frame.substr(0, 40)));
  expectGoodSessionServed();
  EXPECT_TRUE(beforeHello.waitForClose()) << "hello timeout";
  EXPECT_TRUE(afterHello.waitForClose()) << "client timeout";
  expectSessionsBecome(1);
}

TEST_F(Faults, AFloodOfMessagesCoalescesAndErrorsAreCapped) {
  auto flooder = connectSession(daemon_.port());
  nlohmann::json welcome = helloAndWelcome(*flooder, kWidth, kHeight);
  uint32_t seq = 0;
  for (int i = 0; i < 2000; ++i) {
    nlohmann::json camera = welcome["camera"];
    camera["seq"] = ++seq;
    camera["position"][1] = camera["position"][1].get<double>() + 0.0001 * i;
    flooder->sendText(camera.dump());
    flooder->sendText("{not json");
    flooder->sendText(R"({"type":"ack","frame":1000000})");
  }
  expectGoodSessionServed();
  // Acking as it goes, the flooder gets the view of its last input: inputs coalesced.
  bool lastApplied = false;
  while (!lastApplied) {
    std::optional<Frame> frame = nextFrame(*flooder);
    ASSERT_TRUE(frame) << daemon_.log();
    ack(*flooder, frame->header.frame);
    lastApplied = frame->header.seq == seq;
  }
  EXPECT_GT(metricValue(daemon_.port(), "hdof_inputs_coalesced_total"), 0.0);
}

TEST_F(Faults, GarbageBytesCloseTheConnection) {
  std::mt19937 random(7);
  std::string garbage(4096, '\0');
  for (char& c : garbage) c = char(random());
  {
    RawConnection notHttp(daemon_.port());
    ASSERT_TRUE(notHttp.sendBytes(garbage));
    EXPECT_TRUE(notHttp.waitForClose());
  }
  {
    RawConnection afterUpgrade(daemon_.port());
    ASSERT_TRUE(afterUpgrade.handshake());
    ASSERT_TRUE(afterUpgrade.sendText(helloMessage(kWidth, kHeight)));
    ASSERT_TRUE(afterUpgrade.sendBytes(garbage));
    EXPECT_TRUE(afterUpgrade.waitForClose());
  }
  {
    RawConnection unmasked(daemon_.port());  // a client's frames must be masked
    ASSERT_TRUE(unmasked.handshake());
    ASSERT_TRUE(unmasked.sendBytes(std::string("\x81\x05hello", 7)));
    EXPECT_TRUE(unmasked.waitForClose());
  }
  expectSessionsBecome(1);
}

TEST_F(Faults, OpenAndCloseInALoop) {
  for (int i = 0; i < 20; ++i) {
    RawConnection bare(daemon_.port());  // TCP only
    auto client = connectSession(daemon_.port());
    if (i % 2) {
      helloAndWelcome(*client, kWidth, kHeight);
      client->close();
      closeCode(*client);
    }  // else dropped without a close handshake, before hello
  }
  expectSessionsBecome(1);
  EXPECT_EQ(metricValue(daemon_.port(), "hdof_sessions_total"), 11.0);
}

}  // namespace
}  // namespace hdof::test
