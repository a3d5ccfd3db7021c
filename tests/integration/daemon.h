// Test harness for hdof serve: starts the real binary on a free port (--port 0; the port is read
// from the URL it prints), stops it with SIGTERM, and talks to it over HTTP and WebSocket.
#pragma once

#include "net/server_messages.h"
#include "net/ws_client.h"

#include <nlohmann/json.hpp>

#include <sys/types.h>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

namespace hdof::test {

// Built with AddressSanitizer (the sanitizer tier): its allocator keeps freed memory, so RSS
// bounds do not hold there.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

using namespace std::chrono_literals;

// Generous: the machine is slow and shared; nothing here is a timing assert.
constexpr auto kTimeout = 60s;

struct DaemonOptions {
  std::vector<std::string> args;                         // after `hdof serve --port 0`
  std::string config;                                    // JSON; written to a file for --config
  std::vector<std::pair<std::string, std::string>> env;  // added to the environment
  bool waitUntilListening = true;  // false: the constructor returns at once (port() is 0)
};

class Daemon {
 public:
  explicit Daemon(const DaemonOptions& options = {});
  ~Daemon();
  int port() const { return port_; }
  pid_t pid() const { return pid_; }
  // The daemon's resident memory (VmRSS) in bytes; 0 when it cannot be read.
  uint64_t rssBytes() const;
  // SIGTERM, then waits for the exit; returns the exit code (or 128 + signal).
  int stop();
  // What the daemon wrote to stderr so far.
  std::string log() const;

 private:
  pid_t pid_ = -1;
  int stdout_ = -1;
  int port_ = 0;
  std::string logPath_;
  int exitCode_ = -1;
};

struct HttpResponse {
  int status = 0;
  std::string body;
};
HttpResponse httpGet(int port, const std::string& path);
// Any request; `headers` are whole lines without CRLF (a Host header is added unless given).
// The response's head (status line and headers, lowercased names) is in `head`.
struct HttpExchange {
  int status = 0;
  std::string head, body;
  bool closed = false;  // the daemon closed without an answer
};
HttpExchange httpRequest(int port, const std::string& method, const std::string& path,
                         const std::vector<std::string>& headers = {});
// The value of a response header (name lowercase), empty when absent.
std::string headerOf(const HttpExchange& response, const std::string& name);

std::unique_ptr<net::WsClient> connectSession(int port, const std::string& origin = "");
// hello with the viewport (and token, when given); returns the welcome, or fails the test.
nlohmann::json helloAndWelcome(net::WsClient& client, uint32_t width, uint32_t height,
                               const std::string& token = "");
std::string helloMessage(uint32_t width, uint32_t height, const std::string& token = "");

// The next text message as JSON, skipping frames; null after the timeout or a close.
nlohmann::json nextText(net::WsClient& client, std::chrono::milliseconds timeout = kTimeout);

struct Frame {
  net::FrameHeader header;
  nlohmann::json stats;
  std::vector<uint8_t> jpeg;
};
// The next frame, skipping text messages; nothing after the timeout or a close.
std::optional<Frame> nextFrame(net::WsClient& client, std::chrono::milliseconds timeout = kTimeout);
void ack(net::WsClient& client, uint32_t frame);
// Waits for the close and returns its code (0 when none came in time).
int closeCode(net::WsClient& client, std::string* reason = nullptr);
// The same over a bare socket that sends `messages` as text after the handshake: libwebsockets'
// client reports close codes it does not know (1013) as 1002, a browser does not.
int rawCloseCode(int port, const std::vector<std::string>& messages);

// A bare TCP connection to the daemon, for clients that misbehave below the WebSocket API: half
// frames, garbage bytes, no reading at all.
class RawConnection {
 public:
  explicit RawConnection(int port);
  ~RawConnection();
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;
  bool open() const { return fd_ >= 0; }
  int fd() const { return fd_; }
  // The WebSocket upgrade to /session; true when the daemon switched protocols.
  bool handshake();
  // An upgrade to `path` with these extra header lines; the status code of the answer (0: none).
  int upgrade(const std::string& path, const std::vector<std::string>& headers);
  bool sendBytes(const std::string& bytes);
  // One masked text frame (mask 0).
  bool sendText(const std::string& text);
  // Up to `size` bytes (fewer at the end of the stream or after the timeout); empty when none.
  std::string receiveSome(size_t size, std::chrono::milliseconds timeout = kTimeout);
  // Reads and drops bytes until the daemon closes the connection or the timeout: true on a close.
  bool waitForClose(std::chrono::milliseconds timeout = kTimeout);
  void close();

 private:
  int fd_ = -1;
};
// A masked WebSocket text frame of `text` (mask 0), as a client sends it.
std::string maskedTextFrame(const std::string& text);

// Runs `hdof ARGS` to the end; its exit code, stdout and stderr.
struct CommandResult {
  int exitCode = -1;
  std::string out, err;
};
CommandResult runHdof(const std::string& args);
// The value of a Prometheus sample without labels ("hdof_sessions"), -1 when absent.
double metricValue(int port, const std::string& name);

}  // namespace hdof::test
