#include "net/ws_server.h"

#include "net/log.h"
#include "net/message_codec.h"

#include <libwebsockets.h>
#include <nlohmann/json.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace hdof::net {
namespace {

// Error messages queued for a client that does not read them: further ones are counted, not kept.
constexpr size_t kMaxQueuedText = 16;
constexpr size_t kMaxCloseReason = 123;  // RFC 6455: a close frame's payload is at most 125 bytes

double msBetween(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double, std::milli>(to - from).count();
}

std::string header(lws* wsi, lws_token_indexes token) {
  char value[512];
  int length = lws_hdr_copy(wsi, value, sizeof(value), token);
  return length > 0 ? std::string(value, size_t(length)) : std::string();
}

// Compares without stopping at the first difference, so timing does not tell how much matched.
bool sameToken(const std::string& given, const std::string& expected) {
  unsigned char difference = given.size() != expected.size();
  for (size_t i = 0; i < given.size(); ++i)
    difference |= uint8_t(given[i]) ^ uint8_t(expected[i % std::max<size_t>(1, expected.size())]);
  return difference == 0;
}

std::string listenAddress(const ServerOptions& options) {
  return (options.bind.empty() ? "*" : options.bind) + ":" + std::to_string(options.port);
}

// libwebsockets retries a bind that fails every 30 s instead of failing; trying it first says
// why at once. Interface names (eth0) are left to libwebsockets.
void checkCanListen(const ServerOptions& options) {
  sockaddr_in v4{};
  sockaddr_in6 v6{};
  v4.sin_family = AF_INET;
  v4.sin_port = htons(uint16_t(options.port));
  v6.sin6_family = AF_INET6;
  v6.sin6_port = htons(uint16_t(options.port));
  v6.sin6_addr = in6addr_any;
  const sockaddr* address = nullptr;
  socklen_t length = 0;
  if (options.bind.empty()) {
    address = reinterpret_cast<const sockaddr*>(&v6);
    length = sizeof(v6);
  } else if (inet_pton(AF_INET, options.bind.c_str(), &v4.sin_addr) == 1) {
    address = reinterpret_cast<const sockaddr*>(&v4);
    length = sizeof(v4);
  } else if (inet_pton(AF_INET6, options.bind.c_str(), &v6.sin6_addr) == 1) {
    address = reinterpret_cast<const sockaddr*>(&v6);
    length = sizeof(v6);
  } else {
    return;
  }
  int fd = socket(address->sa_family, SOCK_STREAM, 0);
  if (fd < 0) return;
  int one = 1;
  setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  int result = bind(fd, address, length);
  int error = errno;
  close(fd);
  if (result != 0)
    throw ListenError("cannot listen on " + listenAddress(options) + ": " + std::strerror(error) +
                      " (--port 0 picks a free port)");
}

}  // namespace

struct WsServer::Connection {
  uint64_t id = 0;
  lws* wsi = nullptr;
  std::string peer;
  Clock::time_point opened;
  bool welcomed = false;
  std::string rx;  // the text message being received, fragment by fragment
  std::deque<std::string> textOut;
  std::deque<StreamFrame> framesOut;  // at most max_unacked_frames: the render loop sees to it
  std::optional<std::pair<uint16_t, std::string>> closing;  // after textOut is sent
  uint64_t framesSent = 0, bytesSent = 0, errors = 0, dropped = 0;
  uint16_t closeCode = 0;  // the code the daemon closed with; 0: the client closed or vanished
};

struct WsServer::LwsSetup {
  lws_sorted_usec_list_t deadline{};  // first member: the timer callback casts back to LwsSetup
  WsServer* server = nullptr;
  lws_protocols protocols[3]{};
  lws_http_mount root{}, healthz{}, metrics{};
  lws_retry_bo_t retry{};
};

// libwebsockets' C callbacks, forwarded to the server the context belongs to.
struct Callbacks {
  static WsServer& server(lws* wsi) {
    return *static_cast<WsServer*>(lws_context_user(lws_get_context(wsi)));
  }
  static int session(lws* wsi, lws_callback_reasons reason, void* user, void* in, size_t len) {
    static WsServer::Connection* none = nullptr;
    auto& slot = user ? *static_cast<WsServer::Connection**>(user) : none;
    return server(wsi).onSession(wsi, reason, slot, in, len);
  }
  static int http(lws* wsi, lws_callback_reasons reason, void* user, void* in, size_t len) {
    if (user && (reason == LWS_CALLBACK_HTTP || reason == LWS_CALLBACK_HTTP_WRITEABLE ||
                 reason == LWS_CALLBACK_CLOSED_HTTP)) {
      if (int result = server(wsi).onHttp(wsi, reason, *static_cast<std::string**>(user));
          result != 1)
        return result;
    }
    return lws_callback_http_dummy(wsi, reason, user, in, len);
  }
  static void deadline(lws_sorted_usec_list_t* sul) {
    reinterpret_cast<WsServer::LwsSetup*>(sul)->server->shutdownDeadline_ = true;
  }
};

WsServer::WsServer(const ServerOptions& options, SessionTemplate session, RenderLoop& renderLoop,
                   Metrics& metrics)
    : options_(options),
      session_(std::move(session)),
      renderLoop_(renderLoop),
      metrics_(metrics),
      lws_(std::make_unique<LwsSetup>()) {
  lws_set_log_level(LLL_ERR, nullptr);
  LwsSetup& setup = *lws_;
  setup.server = this;
  setup.protocols[0] = {"http", Callbacks::http, sizeof(std::string*), 0, 0, nullptr, 0};
  setup.protocols[1] = {kSubprotocol, Callbacks::session, sizeof(Connection*), 4096, 0, nullptr, 0};

  setup.metrics.mountpoint = "/metrics";
  setup.metrics.mountpoint_len = uint8_t(std::strlen(setup.metrics.mountpoint));
  setup.metrics.origin = "http";
  setup.metrics.origin_protocol = LWSMPRO_CALLBACK;
  setup.healthz = setup.metrics;
  setup.healthz.mountpoint = "/healthz";
  setup.healthz.mount_next = &setup.metrics;
  setup.root.mountpoint = "/";
  setup.root.mountpoint_len = 1;
  setup.root.origin = options_.webRoot.c_str();
  setup.root.def = "index.html";
  setup.root.origin_protocol = LWSMPRO_FILE;
  setup.root.mount_next = &setup.healthz;

  // A client that answers no ping for clientTimeoutS is gone: its session ends.
  setup.retry.secs_since_valid_ping = uint16_t(std::max(1u, options_.clientTimeoutS / 2));
  setup.retry.secs_since_valid_hangup = uint16_t(std::max(2u, options_.clientTimeoutS));

  lws_context_creation_info info{};
  info.port = options_.port;
  info.iface = options_.bind.empty() ? nullptr : options_.bind.c_str();
  info.protocols = setup.protocols;
  info.mounts = &setup.root;
  info.options = LWS_SERVER_OPTION_VALIDATE_UTF8;
  // An IPv4 address to bind to is only honoured on an IPv4 socket.
  if (options_.bind.find(':') == std::string::npos && !options_.bind.empty())
    info.options |= LWS_SERVER_OPTION_DISABLE_IPV6;
  info.user = this;
  info.vhost_name = "hdof";
  info.server_string = "hdof";
  info.retry_and_idle_policy = &setup.retry;
  checkCanListen(options_);
  context_ = lws_create_context(&info);
  if (!context_) throw ListenError("cannot listen on " + listenAddress(options_));
  port_ = lws_get_vhost_listen_port(lws_get_vhost_by_name(context_, "hdof"));
  if (port_ <= 0) {
    lws_context_destroy(context_);
    throw ListenError("cannot listen on " + listenAddress(options_));
  }
}

WsServer::~WsServer() {
  if (context_) lws_context_destroy(context_);
}

void WsServer::run() {
  while (lws_service(context_, 0) >= 0)
    if (stopping_ && (connections_.empty() || shutdownDeadline_)) break;
}

void WsServer::stop() {
  stopRequested_ = true;
  lws_cancel_service(context_);
}

void WsServer::queueFrame(StreamFrame frame) {
  {
    std::lock_guard lock(inboxMutex_);
    inboxFrames_.push_back(std::move(frame));
  }
  lws_cancel_service(context_);
}

void WsServer::sessionFailed(uint64_t session, const std::string& why) {
  {
    std::lock_guard lock(inboxMutex_);
    inboxFailures_.emplace_back(session, why);
  }
  lws_cancel_service(context_);
}

void WsServer::takeInbox() {
  std::vector<StreamFrame> frames;
  std::vector<std::pair<uint64_t, std::string>> failures;
  {
    std::lock_guard lock(inboxMutex_);
    frames.swap(inboxFrames_);
    failures.swap(inboxFailures_);
  }
  for (StreamFrame& frame : frames) {
    auto it = connections_.find(frame.session);
    if (it == connections_.end() || it->second->closing) {
      metrics_.frameDropped();
      if (it != connections_.end()) ++it->second->dropped;
      continue;
    }
    it->second->framesOut.push_back(std::move(frame));
    lws_callback_on_writable(it->second->wsi);
  }
  for (const auto& [session, why] : failures) {
    logEvent("session_failed", "session=" + std::to_string(session) + " error=" + logValue(why));
    if (auto it = connections_.find(session); it != connections_.end())
      closeAfterSending(*it->second, kCloseInternalError, "rendering failed: " + why);
  }
  if (stopRequested_ && !stopping_) {
    stopping_ = true;
    for (auto& [id, connection] : connections_)
      closeAfterSending(*connection, kCloseGoingAway, "the daemon shuts down");
    lws_sul_schedule(context_, 0, &lws_->deadline, Callbacks::deadline, 2 * LWS_US_PER_SEC);
  }
}

int WsServer::onSession(lws* wsi, int reason, Connection*& slot, void* in, size_t len) {
  switch (reason) {
    case LWS_CALLBACK_EVENT_WAIT_CANCELLED:
      takeInbox();
      return 0;
    case LWS_CALLBACK_FILTER_PROTOCOL_CONNECTION:
      return header(wsi, WSI_TOKEN_GET_URI) == kSessionPath ? 0 : 1;
    case LWS_CALLBACK_ESTABLISHED:
      open(wsi, slot);
      return 0;
    case LWS_CALLBACK_RECEIVE:
      return slot ? receive(wsi, *slot, static_cast<const char*>(in), len) : -1;
    case LWS_CALLBACK_SERVER_WRITEABLE:
      return slot ? writeNext(wsi, *slot) : 0;
    case LWS_CALLBACK_CLOSED:
      if (slot) closed(*slot);
      delete slot;
      slot = nullptr;
      return 0;
    default:
      return 0;
  }
}

int WsServer::onHttp(lws* wsi, int reason, std::string*& body) {
  if (reason == LWS_CALLBACK_CLOSED_HTTP) {
    delete body;
    body = nullptr;
    return 1;
  }
  if (reason == LWS_CALLBACK_HTTP_WRITEABLE) {
    if (!body) return 1;
    size_t length = body->size() - LWS_PRE;
    int written = lws_write(wsi, reinterpret_cast<unsigned char*>(body->data()) + LWS_PRE, length,
                            LWS_WRITE_HTTP_FINAL);
    bool complete = written == int(length);
    delete body;
    body = nullptr;
    return complete && lws_http_transaction_completed(wsi) == 0 ? 0 : -1;
  }
  std::string uri = header(wsi, WSI_TOKEN_GET_URI);
  const char* contentType = nullptr;
  std::string text;
  if (uri == "/healthz") {
    contentType = "application/json";
    text =
        nlohmann::json{{"status", "ok"}, {"device", session_.deviceName}, {"sessions", welcomed_}}
            .dump() +
        "\n";
  } else if (uri == "/metrics") {
    contentType = "text/plain; version=0.0.4";
    text = metrics_.prometheusText();
  } else {
    return 1;  // libwebsockets answers (404)
  }
  unsigned char headers[LWS_PRE + 512];
  unsigned char *start = headers + LWS_PRE, *p = start, *end = headers + sizeof(headers) - 1;
  if (lws_add_http_common_headers(wsi, HTTP_STATUS_OK, contentType, text.size(), &p, end) ||
      lws_finalize_write_http_header(wsi, start, &p, end))
    return -1;
  delete body;
  body = new std::string(LWS_PRE, '\0');  // lws_write's headroom, then the body
  *body += text;
  lws_callback_on_writable(wsi);
  return 0;
}

void WsServer::open(lws* wsi, Connection*& slot) {
  auto* c = new Connection;
  c->id = nextId_++;
  c->wsi = wsi;
  c->opened = Clock::now();
  char peer[128] = "";
  lws_get_peer_simple(wsi, peer, sizeof(peer));
  c->peer = peer;
  slot = c;
  connections_[c->id] = c;
  if (stopping_) return closeAfterSending(*c, kCloseGoingAway, "the daemon shuts down");
  if (!options_.allowedOrigins.empty()) {
    std::string origin = header(wsi, WSI_TOKEN_ORIGIN);
    const auto& allowed = options_.allowedOrigins;
    if (std::find(allowed.begin(), allowed.end(), origin) == allowed.end()) {
      sendError(*c, {ErrorCode::NotAllowed, "origin '" + origin + "' is not allowed", "origin"});
      return closeAfterSending(*c, kClosePolicyViolation, "origin not allowed");
    }
  }
  lws_set_timeout(wsi, PENDING_TIMEOUT_USER_OK, int(options_.helloTimeoutS));
}

int WsServer::receive(lws* wsi, Connection& c, const char* data, size_t len) {
  if (c.closing) return 0;  // the session is on its way out: input no longer counts
  if (lws_frame_is_binary(wsi))
    return closeNow(wsi, c, kCloseProtocolError, "binary messages are not part of the protocol");
  if (c.rx.size() + len + lws_remaining_packet_payload(wsi) > options_.limits.maxMessageBytes)
    return closeNow(
        wsi, c, kCloseMessageTooBig,
        "message longer than " + std::to_string(options_.limits.maxMessageBytes) + " bytes");
  c.rx.append(data, len);
  if (!lws_is_final_fragment(wsi)) return 0;
  std::string text = std::move(c.rx);
  c.rx.clear();
  return handleMessage(wsi, c, text);
}

int WsServer::handleMessage(lws* wsi, Connection& c, const std::string& text) {
  Clock::time_point received = Clock::now();
  ParsedMessage parsed = parseClientMessage(text, options_.limits);
  if (!parsed.ok()) {
    sendError(c, parsed.error);
    return 0;
  }
  if (const auto* message = std::get_if<HelloMessage>(&*parsed.message)) {
    if (!c.welcomed) return hello(wsi, c, *message);
    sendError(c, {ErrorCode::NotAllowed, "this session has already said hello", "type"});
    return 0;
  }
  if (!c.welcomed) return closeNow(wsi, c, kCloseProtocolError, "the first message must be hello");
  if (auto error = renderLoop_.apply(c.id, *parsed.message, received)) sendError(c, *error);
  return 0;
}

int WsServer::hello(lws* wsi, Connection& c, const HelloMessage& hello) {
  if (!options_.token.empty() && !(hello.token && sameToken(*hello.token, options_.token))) {
    sendError(
        c, {ErrorCode::NotAllowed,
            hello.token ? "wrong token" : "this daemon needs a token: send it in hello", "token"});
    closeAfterSending(c, kClosePolicyViolation, "missing or wrong token");
    return 0;
  }
  const auto& scenes = session_.sceneNames;
  if (hello.scene && std::find(scenes.begin(), scenes.end(), *hello.scene) == scenes.end()) {
    sendError(c, {ErrorCode::NotAllowed,
                  "this daemon serves the scene '" + scenes.front() + "', not '" +
                      hello.scene->substr(0, 200) + "'",
                  "scene"});
    return 0;
  }
  if (welcomed_ >= int(options_.maxSessions)) {
    sendError(c, {ErrorCode::Busy,
                  std::to_string(welcomed_) + " sessions are open, the most this daemon takes: "
                                              "try again later",
                  ""});
    closeAfterSending(c, kCloseTryAgainLater, "too many sessions");
    return 0;
  }
  c.welcomed = true;
  ++welcomed_;
  lws_set_timeout(wsi, NO_PENDING_TIMEOUT, 0);
  Welcome welcome = session_.welcome;
  welcome.session = std::to_string(c.id);
  welcome.limits = options_.limits;
  sendText(c, welcomeMessage(welcome));
  renderLoop_.addSession(c.id, session_.defaults, hello.viewport);
  metrics_.sessionStarted();
  logEvent("session_start", "session=" + std::to_string(c.id) + " peer=" + logValue(c.peer) +
                                " viewport=" + std::to_string(hello.viewport.width) + "x" +
                                std::to_string(hello.viewport.height));
  return 0;
}

int WsServer::writeNext(lws* wsi, Connection& c) {
  if (!c.textOut.empty()) {
    std::string text = std::move(c.textOut.front());
    c.textOut.pop_front();
    std::vector<unsigned char> buffer(LWS_PRE + text.size());
    std::memcpy(buffer.data() + LWS_PRE, text.data(), text.size());
    if (lws_write(wsi, buffer.data() + LWS_PRE, text.size(), LWS_WRITE_TEXT) < int(text.size()))
      return -1;
    if (!c.textOut.empty() || c.closing || !c.framesOut.empty()) lws_callback_on_writable(wsi);
    return 0;
  }
  if (c.closing) return closeNow(wsi, c, c.closing->first, c.closing->second);
  if (c.framesOut.empty()) return 0;
  StreamFrame frame = std::move(c.framesOut.front());
  c.framesOut.pop_front();

  Clock::time_point now = Clock::now();
  const FrameRequest& request = frame.plan.request;
  FrameStatsMessage stats;
  stats.frame = frame.plan.frame;
  stats.mode = modeName(request.mode);
  stats.passesMs = frame.stats.passMs;
  stats.gpuMs = frame.stats.gpuMs;
  stats.raysShot = frame.stats.raysShot;
  stats.maskCoverage = frame.stats.maskCoverage;
  stats.encodeMs = frame.jpeg.encodeMs;
  stats.queueWaitMs = std::max(0.0, msBetween(frame.renderedAt, now) - frame.jpeg.encodeMs);
  stats.bytes = frame.jpeg.bytes.size();
  if (frame.plan.inputReceived) stats.inputToSendMs = msBetween(*frame.plan.inputReceived, now);
  stats.jpegQuality = frame.plan.jpegQuality;
  stats.accumulatedFrames = frame.plan.accumulatedFrames;
  stats.focusDistance = request.lens.focusDistance;
  std::vector<uint8_t> message = frameMessage(
      {frame.plan.frame, request.settings.width, request.settings.height, frame.plan.seq},
      frameStatsJson(stats), frame.jpeg.bytes, LWS_PRE);
  size_t length = message.size() - LWS_PRE;
  if (lws_write(wsi, message.data() + LWS_PRE, length, LWS_WRITE_BINARY) < int(length)) return -1;
  ++c.framesSent;
  c.bytesSent += stats.bytes;
  metrics_.frameSent(stats.bytes, stats.encodeMs, stats.inputToSendMs);
  if (!c.framesOut.empty()) lws_callback_on_writable(wsi);
  return 0;
}

void WsServer::closed(Connection& c) {
  for (size_t i = 0; i < c.framesOut.size(); ++i) metrics_.frameDropped();
  c.dropped += c.framesOut.size();
  std::string close = c.closeCode ? std::to_string(c.closeCode) : "client";
  if (c.welcomed) {
    renderLoop_.removeSession(c.id);
    --welcomed_;
    metrics_.sessionEnded();
    char duration[32];
    std::snprintf(duration, sizeof(duration), "%.1f", msBetween(c.opened, Clock::now()) * 1e-3);
    logEvent("session_end",
             "session=" + std::to_string(c.id) + " peer=" + logValue(c.peer) +
                 " duration_s=" + duration + " frames=" + std::to_string(c.framesSent) +
                 " bytes=" + std::to_string(c.bytesSent) + " errors=" + std::to_string(c.errors) +
                 " dropped=" + std::to_string(c.dropped) + " close=" + close);
  } else if (c.closeCode) {
    logEvent("connection_refused", "peer=" + logValue(c.peer) + " close=" + close);
  }
  connections_.erase(c.id);
}

void WsServer::sendError(Connection& c, const ProtocolError& error) {
  metrics_.error(error.code);
  ++c.errors;
  if (c.textOut.size() < kMaxQueuedText) sendText(c, errorMessage(error));
}

void WsServer::sendText(Connection& c, std::string text) {
  c.textOut.push_back(std::move(text));
  lws_callback_on_writable(c.wsi);
}

void WsServer::closeAfterSending(Connection& c, uint16_t code, const std::string& reason) {
  if (c.closing) return;
  c.closing.emplace(code, reason);
  lws_callback_on_writable(c.wsi);
}

int WsServer::closeNow(lws* wsi, Connection& c, uint16_t code, const std::string& reason) {
  std::string shown = reason.substr(0, kMaxCloseReason);
  lws_close_reason(wsi, lws_close_status(code), reinterpret_cast<unsigned char*>(shown.data()),
                   shown.size());
  metrics_.closed(code);
  c.closeCode = code;
  return -1;
}

}  // namespace hdof::net
