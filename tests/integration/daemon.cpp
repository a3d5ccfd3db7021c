#include "daemon.h"

#include "common/scratch_dir.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace hdof::test {
namespace {

std::string uniquePath(const std::string& name) {
  static std::atomic<int> counter{0};
  return (scratchDir("serve-test") / (std::to_string(counter++) + "-" + name)).string();
}

}  // namespace

Daemon::Daemon(const DaemonOptions& options) {
  std::vector<std::string> args = {HDOF_BINARY, "serve", "--port", "0"};
  if (!options.config.empty()) {
    std::string path = uniquePath("config.json");
    std::ofstream(path) << options.config;
    args.insert(args.end(), {"--config", path});
  }
  args.insert(args.end(), options.args.begin(), options.args.end());
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e)
    if (!std::string(*e).starts_with("HDOF_TOKEN=")) env.push_back(*e);
  for (const auto& [name, value] : options.env) env.push_back(name + "=" + value);
  std::vector<char*> argv, envp;
  for (std::string& a : args) argv.push_back(a.data());
  for (std::string& e : env) envp.push_back(e.data());
  argv.push_back(nullptr);
  envp.push_back(nullptr);

  logPath_ = uniquePath("daemon.log");
  int logFd = open(logPath_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  int pipeFds[2];
  if (logFd < 0 || pipe(pipeFds) != 0) throw std::runtime_error("cannot make the daemon's pipes");
  pid_ = fork();
  if (pid_ == 0) {
    // A test program that dies (a sanitizer's abort) takes its daemon with it.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    dup2(pipeFds[1], 1);
    dup2(logFd, 2);
    close(pipeFds[0]);
    execve(argv[0], argv.data(), envp.data());
    _exit(127);
  }
  close(pipeFds[1]);
  close(logFd);
  stdout_ = pipeFds[0];

  if (!options.waitUntilListening) return;
  // The daemon prints the URL to open once it listens.
  std::string output;
  auto deadline = std::chrono::steady_clock::now() + kTimeout;
  std::smatch match;
  static const std::regex url("http://[^:]+:([0-9]+)/");
  while (!std::regex_search(output, match, url)) {
    int left = int(std::chrono::duration_cast<std::chrono::milliseconds>(
                       deadline - std::chrono::steady_clock::now())
                       .count());
    pollfd fd{stdout_, POLLIN, 0};
    char buffer[256];
    ssize_t n = left > 0 && poll(&fd, 1, left) > 0 ? read(stdout_, buffer, sizeof(buffer)) : 0;
    if (n <= 0) {
      stop();
      throw std::runtime_error("hdof serve did not start; its log:\n" + log());
    }
    output.append(buffer, size_t(n));
  }
  port_ = std::stoi(match[1]);
}

Daemon::~Daemon() {
  stop();
  if (stdout_ >= 0) close(stdout_);
}

int Daemon::stop() {
  if (pid_ <= 0) return exitCode_;
  kill(pid_, SIGTERM);
  int status = 0;
  for (int i = 0; i < 300; ++i) {  // 30 s
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      exitCode_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      return exitCode_;
    }
    std::this_thread::sleep_for(100ms);
  }
  kill(pid_, SIGKILL);
  waitpid(pid_, &status, 0);
  pid_ = -1;
  exitCode_ = 128 + SIGKILL;
  return exitCode_;
}

uint64_t Daemon::rssBytes() const {
  std::ifstream in("/proc/" + std::to_string(pid_) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.starts_with("VmRSS:")) return std::stoull(line.substr(6)) * 1024;
  return 0;
}

std::string Daemon::log() const {
  std::ifstream in(logPath_);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

namespace {

int connectLoopback(int port) {
  int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(uint16_t(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  timeval timeout{60, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof(timeout));
  if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

bool sendAll(int fd, const std::string& bytes) {
  return send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL) == ssize_t(bytes.size());
}

bool receiveExactly(int fd, uint8_t* out, size_t size) {
  for (size_t done = 0; done < size;) {
    ssize_t n = recv(fd, out + done, size - done, 0);
    if (n <= 0) return false;
    done += size_t(n);
  }
  return true;
}

}  // namespace

RawConnection::RawConnection(int port) : fd_(connectLoopback(port)) {}

RawConnection::~RawConnection() { close(); }

void RawConnection::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool RawConnection::handshake() {
  return upgrade("/session", {"Sec-WebSocket-Protocol: hdof.v1"}) == 101;
}

int RawConnection::upgrade(const std::string& path, const std::vector<std::string>& headers) {
  std::string request = "GET " + path +
                        " HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\n"
                        "Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
                        "Sec-WebSocket-Version: 13\r\n";
  for (const std::string& line : headers) request += line + "\r\n";
  request += "\r\n";
  std::string response;
  bool ok = open() && sendAll(fd_, request);
  for (uint8_t byte; ok && response.find("\r\n\r\n") == std::string::npos;) {
    ok = receiveExactly(fd_, &byte, 1);
    response += char(byte);
  }
  if (!ok || !response.starts_with("HTTP/1.")) return 0;
  return std::atoi(response.c_str() + 9);
}

bool RawConnection::sendBytes(const std::string& bytes) { return open() && sendAll(fd_, bytes); }

bool RawConnection::sendText(const std::string& text) { return sendBytes(maskedTextFrame(text)); }

std::string RawConnection::receiveSome(size_t size, std::chrono::milliseconds timeout) {
  std::string bytes(size, '\0');
  pollfd fd{fd_, POLLIN, 0};
  if (!open() || poll(&fd, 1, int(timeout.count())) <= 0) return {};
  ssize_t n = recv(fd_, bytes.data(), size, 0);
  bytes.resize(n > 0 ? size_t(n) : 0);
  return bytes;
}

bool RawConnection::waitForClose(std::chrono::milliseconds timeout) {
  auto deadline = std::chrono::steady_clock::now() + timeout;
  char buffer[4096];
  while (open()) {
    auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    pollfd fd{fd_, POLLIN, 0};
    if (left <= 0ms || poll(&fd, 1, int(left.count())) <= 0) return false;
    if (recv(fd_, buffer, sizeof(buffer), 0) <= 0) return true;
  }
  return false;
}

std::string maskedTextFrame(const std::string& text) {
  std::string frame = {char(0x81)};
  if (text.size() < 126) {
    frame += char(0x80 | text.size());
  } else {
    frame += char(0x80 | 126);
    frame += char(text.size() >> 8);
    frame += char(text.size() & 0xff);
  }
  return frame + std::string(4, '\0') + text;
}

int rawCloseCode(int port, const std::vector<std::string>& messages) {
  RawConnection connection(port);
  bool ok = connection.handshake();
  for (const std::string& text : messages) ok = ok && connection.sendText(text);
  int code = 0;
  int fd = connection.fd();
  while (ok && code == 0) {
    uint8_t head[2];
    ok = receiveExactly(fd, head, 2);
    uint64_t length = head[1] & 0x7f;
    uint8_t extended[8];
    if (ok && length == 126 && (ok = receiveExactly(fd, extended, 2)))
      length = uint64_t(extended[0]) << 8 | extended[1];
    if (ok && length == 127 && (ok = receiveExactly(fd, extended, 8)))
      for (int i = 0; i < 8; ++i) length = i ? length << 8 | extended[i] : extended[i];
    std::vector<uint8_t> payload(length);
    ok = ok && receiveExactly(fd, payload.data(), payload.size());
    if (ok && (head[0] & 0x0f) == 0x8) code = length >= 2 ? payload[0] << 8 | payload[1] : 1005;
  }
  return code;
}

CommandResult runHdof(const std::string& args) {
  std::string out = uniquePath("out.txt"), err = uniquePath("err.txt");
  std::string command =
      std::string(HDOF_BINARY) + " " + args + " >" + out + " 2>" + err + " </dev/null";
  int status = std::system(command.c_str());
  auto read = [](const std::string& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), read(out), read(err)};
}

double metricValue(int port, const std::string& name) {
  std::string text = httpGet(port, "/metrics").body;
  std::string prefix = "\n" + name + " ";
  auto at = text.find(prefix);
  return at == std::string::npos ? -1.0 : std::atof(text.c_str() + at + prefix.size());
}

HttpResponse httpGet(int port, const std::string& path) {
  HttpResponse response;
  int fd = connectLoopback(port);
  if (fd < 0) return response;
  std::string request = "GET " + path + " HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n";
  if (send(fd, request.data(), request.size(), 0) != ssize_t(request.size())) {
    close(fd);
    return response;
  }
  std::string text;
  char buffer[4096];
  for (ssize_t n; (n = recv(fd, buffer, sizeof(buffer), 0)) > 0;) text.append(buffer, size_t(n));
  close(fd);
  if (text.starts_with("HTTP/1.")) response.status = std::atoi(text.c_str() + 9);
  if (auto body = text.find("\r\n\r\n"); body != std::string::npos)
    response.body = text.substr(body + 4);
  return response;
}

HttpExchange httpRequest(int port, const std::string& method, const std::string& path,
                         const std::vector<std::string>& headers) {
  HttpExchange response;
  int fd = connectLoopback(port);
  if (fd < 0) return response;
  std::string request = method + " " + path + " HTTP/1.1\r\nConnection: close\r\n";
  bool hasHost = false;
  for (const std::string& line : headers) {
    request += line + "\r\n";
    hasHost = hasHost || line.starts_with("Host:");
  }
  if (!hasHost) request += "Host: 127.0.0.1:" + std::to_string(port) + "\r\n";
  request += "\r\n";
  std::string text;
  if (sendAll(fd, request)) {
    char buffer[4096];
    for (ssize_t n; (n = recv(fd, buffer, sizeof(buffer), 0)) > 0;) text.append(buffer, size_t(n));
  }
  close(fd);
  response.closed = text.empty();
  if (text.starts_with("HTTP/1.")) response.status = std::atoi(text.c_str() + 9);
  auto end = text.find("\r\n\r\n");
  response.head = text.substr(0, end);
  for (char& c : response.head) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (end != std::string::npos) response.body = text.substr(end + 4);
  return response;
}

std::string headerOf(const HttpExchange& response, const std::string& name) {
  auto at = response.head.find("\r\n" + name + ":");
  if (at == std::string::npos) return "";
  auto start = response.head.find_first_not_of(' ', at + name.size() + 3);
  auto end = response.head.find("\r\n", start);
  return response.head.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

std::unique_ptr<net::WsClient> connectSession(int port, const std::string& origin) {
  net::WsClientOptions options;
  options.port = port;
  options.origin = origin;
  auto client = std::make_unique<net::WsClient>(options);
  EXPECT_TRUE(client->connected(kTimeout)) << "no WebSocket connection to port " << port;
  return client;
}

std::string helloMessage(uint32_t width, uint32_t height, const std::string& token) {
  nlohmann::json hello = {
      {"type", "hello"}, {"protocol", 1}, {"viewport", {{"width", width}, {"height", height}}}};
  if (!token.empty()) hello["token"] = token;
  return hello.dump();
}

nlohmann::json helloAndWelcome(net::WsClient& client, uint32_t width, uint32_t height,
                               const std::string& token) {
  client.sendText(helloMessage(width, height, token));
  nlohmann::json welcome = nextText(client);
  EXPECT_EQ(welcome.value("type", ""), "welcome") << welcome.dump();
  return welcome;
}

namespace {

// The next message of this kind (skipping the others) or the close; nothing after the timeout.
std::optional<net::WsMessage> next(net::WsClient& client, net::WsMessage::Kind kind,
                                   std::chrono::milliseconds timeout) {
  auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    auto message = client.receive(std::max(left, 0ms));
    if (!message || message->kind == kind || message->kind == net::WsMessage::Kind::Closed)
      return message;
  }
}

}  // namespace

nlohmann::json nextText(net::WsClient& client, std::chrono::milliseconds timeout) {
  auto message = next(client, net::WsMessage::Kind::Text, timeout);
  if (!message || message->kind != net::WsMessage::Kind::Text) return nullptr;
  return nlohmann::json::parse(message->text, nullptr, false);
}

std::optional<Frame> nextFrame(net::WsClient& client, std::chrono::milliseconds timeout) {
  auto message = next(client, net::WsMessage::Kind::Binary, timeout);
  if (!message || message->kind != net::WsMessage::Kind::Binary) return std::nullopt;
  auto parsed = net::parseFrameMessage(message->binary);
  EXPECT_TRUE(parsed) << "a binary message that is not a frame";
  if (!parsed) return std::nullopt;
  Frame frame;
  frame.header = parsed->header;
  frame.stats = nlohmann::json::parse(parsed->stats, nullptr, false);
  frame.jpeg.assign(parsed->jpeg.begin(), parsed->jpeg.end());
  return frame;
}

void ack(net::WsClient& client, uint32_t frame) {
  client.sendText(nlohmann::json{{"type", "ack"}, {"frame", frame}}.dump());
}

int closeCode(net::WsClient& client, std::string* reason) {
  auto message = next(client, net::WsMessage::Kind::Closed, kTimeout);
  if (!message) return 0;
  if (reason) *reason = message->closeReason;
  return message->closeCode;
}

}  // namespace hdof::test
