// A blocking WebSocket client on libwebsockets: one connection with its own context and service
// thread, messages in and out through locked queues. For the integration tests, benchmarks and
// load generators that talk to hdof serve.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

struct lws;
struct lws_context;
struct lws_protocols;

namespace hdof::net {

struct WsClientOptions {
  std::string host = "127.0.0.1";
  int port = 0;
  std::string path = "/session";
  std::string protocol = "hdof.v1";
  // The Origin header's host[:port] (libwebsockets adds "http://"), when set. Without one the
  // daemon takes the client for a program, not a browser page, and lets it in unless
  // allowed_origins is set (net/access_policy.h).
  std::string origin;
};

struct WsMessage {
  enum class Kind { Text, Binary, Closed } kind = Kind::Text;
  std::string text;             // Text
  std::vector<uint8_t> binary;  // Binary
  int closeCode = 0;  // Closed: the server's close code, 1006 when it sent none, 0 for a failed
                      // connection
  std::string closeReason;  // Closed: the server's reason, or why the connection failed
};

class WsClient {
 public:
  // Starts connecting; connected() or receive() tell how it went.
  explicit WsClient(const WsClientOptions& options);
  ~WsClient();  // drops the connection without a close handshake, as a vanishing client would
  WsClient(const WsClient&) = delete;
  WsClient& operator=(const WsClient&) = delete;

  // Waits until the handshake is done (true, even when the server has closed again since) or
  // failed / timed out (false).
  bool connected(std::chrono::milliseconds timeout);
  void sendText(std::string text);
  void sendBinary(std::vector<uint8_t> data);
  // The next message, or nothing after the timeout. After a Closed message, no more come.
  std::optional<WsMessage> receive(std::chrono::milliseconds timeout);
  // Starts a normal close (1000).
  void close();

 private:
  friend struct WsClientCallbacks;
  int onEvent(lws* wsi, int reason, void* in, size_t len);
  void push(WsMessage message);

  std::string protocolName_;
  std::string hostHeader_;
  std::unique_ptr<lws_protocols[]> protocols_;  // the context points into both
  lws_context* context_ = nullptr;
  lws* wsi_ = nullptr;  // the service thread's
  std::thread thread_;
  bool stopping_ = false;  // under mutex_

  std::mutex mutex_;
  std::condition_variable changed_;
  enum class State { Connecting, Open, Closed } state_ = State::Connecting;
  bool opened_ = false;
  struct Outgoing {
    std::vector<uint8_t> data;
    bool binary;
  };
  std::deque<Outgoing> outgoing_;
  bool closeRequested_ = false;
  std::deque<WsMessage> incoming_;
  std::vector<uint8_t> partial_;  // the message being received
  int closeCode_ = 1006;
  std::string closeReason_;
};

}  // namespace hdof::net
