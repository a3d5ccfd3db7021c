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
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

namespace hdof::net {
namespace {

// Error messages queued for a client that does not read them: further ones are counted, not kept.
constexpr size_t kMaxQueuedText = 16;
constexpr size_t kMaxCloseReason = 123;  // RFC 6455: a close frame's payload is at most 125 bytes
constexpr lws_usec_t kTickUs = LWS_US_PER_SEC / 4;  // how often tick() looks at pings and cut-offs
// Pings go out this often (or every client_timeout_s / 3 when that is shorter); a session that
// leaves one unanswered for kPingGrace is not rendered for until it answers.
constexpr auto kPingEvery = std::chrono::seconds(2);
constexpr auto kPingGrace = std::chrono::seconds(1);
// A ping's payload: 64 random bits in hex (text: libwebsockets checks a pong's payload as UTF-8).
constexpr size_t kPingBytes = 16;
// How long the daemon, on its way out, waits for slow clients to receive the end of their session.
constexpr auto kLingerAtExit = std::chrono::seconds(2);
using PingPayload = std::array<char, kPingBytes>;

// On every HTTP response: no MIME sniffing, and the page may load and connect to its own origin
// only (the client is plain ES modules, no inline script or style; frames are drawn from blobs).
constexpr std::pair<const char*, const char*> kSecurityHeaders[] = {
    {"x-content-type-options:", "nosniff"},
    {"content-security-policy:",
     "default-src 'self'; img-src 'self' blob: data:; connect-src 'self'; object-src 'none'; "
     "base-uri 'none'; frame-ancestors 'none'; form-action 'none'"},
    {"referrer-policy:", "no-referrer"},
};

double msBetween(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double, std::milli>(to - from).count();
}

// The header's value; nothing when the request has none. A value too long to read comes back as
// "?", which no origin or host check accepts.
std::optional<std::string> headerValue(lws* wsi, lws_token_indexes token) {
  int total = lws_hdr_total_length(wsi, token);
  if (total <= 0) return std::nullopt;
  std::string value(size_t(total) + 1, '\0');
  int length = lws_hdr_copy(wsi, value.data(), int(value.size()), token);
  if (length < 0 || length > 4096) return "?";
  value.resize(size_t(length));
  return value;
}

std::string header(lws* wsi, lws_token_indexes token) {
  return headerValue(wsi, token).value_or("");
}

// Whether the comma-separated Sec-WebSocket-Protocol list names `protocol`.
bool listsProtocol(const std::string& list, const std::string& protocol) {
  size_t start = 0;
  while (start <= list.size()) {
    size_t comma = std::min(list.find(',', start), list.size());
    std::string item = list.substr(start, comma - start);
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (item == protocol) return true;
    start = comma + 1;
  }
  return false;
}

const char* contentType(const std::string& path) {
  static const std::pair<const char*, const char*> kTypes[] = {
      {".html", "text/html; charset=utf-8"},
      {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},
      {".svg", "image/svg+xml"},
      {".png", "image/png"},
      {".jpg", "image/jpeg"},
      {".ico", "image/x-icon"},
      {".txt", "text/plain; charset=utf-8"},
      {".map", "application/json"},
  };
  for (const auto& [extension, type] : kTypes)
    if (path.ends_with(extension)) return type;
  return "application/octet-stream";
}

// Writes a whole response (status, headers, body) at once, as libwebsockets' own error pages do;
// HEAD gets the headers only. Then ends the transaction (unless the caller leaves that to
// libwebsockets): 0 to keep the connection, -1 to close it.
int respond(lws* wsi, unsigned status, const char* type, const std::string& body, bool head,
            const char* allow = nullptr, bool complete = true) {
  std::vector<unsigned char> buffer(LWS_PRE + 2048 + body.size());
  unsigned char *start = buffer.data() + LWS_PRE, *p = start;
  unsigned char* end = buffer.data() + buffer.size() - body.size() - 1;
  auto add = [&](const char* name, const char* value) {
    return lws_add_http_header_by_name(wsi, reinterpret_cast<const unsigned char*>(name),
                                       reinterpret_cast<const unsigned char*>(value),
                                       int(std::strlen(value)), &p, end) == 0;
  };
  bool ok = lws_add_http_common_headers(wsi, status, type, body.size(), &p, end) == 0;
  for (const auto& [name, value] : kSecurityHeaders) ok = ok && add(name, value);
  ok = ok && add("cache-control:", "no-store");
  if (allow) ok = ok && add("allow:", allow);
  ok = ok && lws_finalize_http_header(wsi, &p, end) == 0;
  if (!ok) return -1;
  if (!head) {
    std::memcpy(p, body.data(), body.size());
    p += body.size();
  }
  int length = int(p - start);
  if (lws_write(wsi, start, size_t(length), LWS_WRITE_HTTP) != length) return -1;
  if (!complete) return 0;
  return lws_http_transaction_completed(wsi) ? -1 : 0;
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
  std::deque<StreamFrame> framesOut;  // at most max_unacked_frames: the oldest is dropped
  std::optional<std::pair<uint16_t, std::string>> closing;  // after textOut is sent
  bool choked = false;       // a frame went out and the socket has not drained since
  bool sendBlocked = false;  // as the render loop was last told
  // Liveness: the payloads of recent pings, and when the client last echoed one.
  std::deque<PingPayload> pings;
  bool pingDue = false;
  Clock::time_point lastPing, lastPong;
  std::optional<Clock::time_point> pingUnanswered;  // when the oldest unanswered ping went out
  bool unresponsive = false;  // it has left a ping unanswered for kPingGrace: not reading now
  bool timedOut = false;
  uint64_t framesSent = 0, bytesSent = 0, errors = 0, dropped = 0;
  uint16_t closeCode = 0;  // the code the daemon closed with; 0: the client closed or vanished
};

struct WsServer::LwsSetup {
  // A timer's callback casts its list entry back to the Timer (the entry is its first member).
  struct Timer {
    lws_sorted_usec_list_t sul{};
    WsServer* server = nullptr;
  };
  Timer deadline, tick;
  lws_protocols protocols[3]{};
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
    std::optional<int> result = server(wsi).onHttp(wsi, reason, in);
    return result ? *result : lws_callback_http_dummy(wsi, reason, user, in, len);
  }
  static WsServer& timerServer(lws_sorted_usec_list_t* sul) {
    return *reinterpret_cast<WsServer::LwsSetup::Timer*>(sul)->server;
  }
  static void deadline(lws_sorted_usec_list_t* sul) { timerServer(sul).shutdownDeadline_ = true; }
  static void tick(lws_sorted_usec_list_t* sul) { timerServer(sul).tick(); }
};

WsServer::WsServer(const ServerOptions& options, SessionTemplate session, RenderLoop& renderLoop,
                   Metrics& metrics)
    : options_(options),
      session_(std::move(session)),
      renderLoop_(renderLoop),
      metrics_(metrics),
      lws_(std::make_unique<LwsSetup>()),
      random_(std::random_device{}()) {
  lws_set_log_level(LLL_ERR, nullptr);
  if (!options_.webRoot.empty()) {
    std::error_code error;
    webRoot_ = std::filesystem::canonical(options_.webRoot, error).string();
  }
  LwsSetup& setup = *lws_;
  setup.deadline.server = setup.tick.server = this;
  // Every HTTP request (no mounts) and every upgrade comes to "http" first; only hdof.v1 becomes
  // a session.
  setup.protocols[0] = {"http", Callbacks::http, 0, 0, 0, nullptr, 0};
  setup.protocols[1] = {kSubprotocol, Callbacks::session, sizeof(Connection*), 4096, 0, nullptr, 0};
  // libwebsockets' own idle pings would count any pong, even one sent without reading: liveness
  // is the server's own pings (tick()), so these are off (zero: no validity timer).
  setup.retry.secs_since_valid_ping = 0;
  setup.retry.secs_since_valid_hangup = 0;

  lws_context_creation_info info{};
  info.port = options_.port;
  info.iface = options_.bind.empty() ? nullptr : options_.bind.c_str();
  info.protocols = setup.protocols;
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
  access_ =
      AccessPolicy::forServer(options_.bind, port_, options_.allowedOrigins, options_.allowedHosts);
  lws_sul_schedule(context_, 0, &setup.tick.sul, Callbacks::tick, kTickUs);
}

WsServer::~WsServer() {
  if (context_) lws_context_destroy(context_);
  lingering_.finish(kLingerAtExit);
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
    Connection& c = *it->second;
    c.framesOut.push_back(std::move(frame));
    // The render loop keeps it from growing (it stops the session while the list is full); if
    // frames come anyway, the oldest go.
    while (c.framesOut.size() > std::max<size_t>(1, options_.limits.maxUnackedFrames)) {
      dropFrame(c, c.framesOut.front());
      c.framesOut.pop_front();
    }
    updateSendBlocked(c);
    lws_callback_on_writable(c.wsi);
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
    lws_sul_schedule(context_, 0, &lws_->deadline.sul, Callbacks::deadline, 2 * LWS_US_PER_SEC);
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
    case LWS_CALLBACK_RECEIVE_PONG:
      if (slot) pong(*slot, in, len);
      return 0;
    case LWS_CALLBACK_SERVER_WRITEABLE:
      return slot ? writeNext(wsi, *slot) : 0;
    case LWS_CALLBACK_CLOSED:
      lingering_.add(lws_get_socket_fd(wsi));
      if (slot) closed(*slot);
      delete slot;
      slot = nullptr;
      return 0;
    default:
      return 0;
  }
}

std::optional<int> WsServer::onHttp(lws* wsi, int reason, void* in) {
  switch (reason) {
    case LWS_CALLBACK_HTTP:
      return httpRequest(wsi);
    case LWS_CALLBACK_HTTP_CONFIRM_UPGRADE:
      return confirmUpgrade(wsi, static_cast<const char*>(in));
    case LWS_CALLBACK_FILTER_PROTOCOL_CONNECTION:
      return 1;  // an upgrade that asked for the protocol "http" by name: never a session
    default:
      return std::nullopt;
  }
}

// Before any upgrade: only a WebSocket at /session that asks for hdof.v1, from an allowed Host.
// Anything else gets an HTTP error (returning 1: libwebsockets ends the transaction).
int WsServer::confirmUpgrade(lws* wsi, const char* upgrade) {
  auto refuse = [&](unsigned status, const std::string& why) {
    return respond(wsi, status, "text/plain; charset=utf-8", why + "\n", false, nullptr, false) == 0
               ? 1
               : -1;
  };
  if (!access_.hostAllowed(headerValue(wsi, WSI_TOKEN_HOST)))
    return refuse(HTTP_STATUS_FORBIDDEN, "this Host is not allowed (see allowed_hosts)");
  if (!upgrade || std::string(upgrade) != "websocket")
    return refuse(HTTP_STATUS_BAD_REQUEST, "only WebSocket upgrades, at /session");
  if (header(wsi, WSI_TOKEN_GET_URI) != kSessionPath)
    return refuse(HTTP_STATUS_NOT_FOUND, "WebSocket sessions are at /session");
  std::string protocols = header(wsi, WSI_TOKEN_PROTOCOL);
  if (!listsProtocol(protocols, kSubprotocol) || listsProtocol(protocols, "http"))
    return refuse(HTTP_STATUS_BAD_REQUEST, std::string("sessions need the WebSocket subprotocol ") +
                                               kSubprotocol + " (protocol/README.md)");
  return 0;
}

int WsServer::httpRequest(lws* wsi) {
  bool head = lws_hdr_total_length(wsi, WSI_TOKEN_HEAD_URI) > 0;
  bool get = lws_hdr_total_length(wsi, WSI_TOKEN_GET_URI) > 0;
  const char* text = "text/plain; charset=utf-8";
  if (!access_.hostAllowed(headerValue(wsi, WSI_TOKEN_HOST)))
    return respond(wsi, HTTP_STATUS_FORBIDDEN, text,
                   "this Host is not allowed (see allowed_hosts)\n", head);
  if (!get && !head) {
    respond(wsi, HTTP_STATUS_METHOD_NOT_ALLOWED, text, "only GET and HEAD\n", false, "GET, HEAD");
    return -1;  // a body may follow a POST or PUT: close rather than read it
  }
  std::string uri = header(wsi, head ? WSI_TOKEN_HEAD_URI : WSI_TOKEN_GET_URI);
  if (uri == "/healthz") return healthz(wsi, head);
  if (uri == "/metrics") {
    RenderHealth health = renderLoop_.health();
    std::string body = metrics_.prometheusText();
    body +=
        "# HELP hdof_healthy 1 when /healthz answers ok (render thread and device).\n"
        "# TYPE hdof_healthy gauge\nhdof_healthy " +
        std::string(health.ok() ? "1" : "0") +
        "\n# HELP hdof_render_heartbeat_age_seconds Since the render thread last came round "
        "its loop.\n# TYPE hdof_render_heartbeat_age_seconds gauge\n"
        "hdof_render_heartbeat_age_seconds " +
        nlohmann::json(health.heartbeatAgeS).dump() + "\n";
    return respond(wsi, HTTP_STATUS_OK, "text/plain; version=0.0.4", body, head);
  }
  return serveFile(wsi, uri);
}

int WsServer::healthz(lws* wsi, bool head) {
  RenderHealth health = renderLoop_.health();
  const char* thread = !health.threadRunning ? "stopped" : health.stalled ? "stalled" : "running";
  nlohmann::json body = {{"status", health.ok() ? "ok" : "failing"},
                         {"device", session_.deviceName},
                         {"device_state", health.deviceLost ? "lost" : "ok"},
                         {"render_thread", thread},
                         {"heartbeat_age_s", std::round(health.heartbeatAgeS * 1000.0) / 1000.0},
                         {"sessions", welcomed_}};
  if (!health.ok())
    body["reason"] = !health.failure.empty() ? health.failure
                     : health.stalled        ? "no heartbeat from the render thread"
                                             : "the render thread is not running";
  return respond(wsi, health.ok() ? HTTP_STATUS_OK : HTTP_STATUS_SERVICE_UNAVAILABLE,
                 "application/json",
                 body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n", head);
}

// A file of the web root: its real path (symlinks resolved) must lie inside the web root's, and
// no path segment may start with a dot. Directories serve their index.html.
int WsServer::serveFile(lws* wsi, const std::string& uri) {
  bool head = lws_hdr_total_length(wsi, WSI_TOKEN_HEAD_URI) > 0;
  auto notFound = [&] {
    return respond(wsi, HTTP_STATUS_NOT_FOUND, "text/plain; charset=utf-8", "not found\n", head);
  };
  if (webRoot_.empty() || !uri.starts_with('/') || uri.find('\0') != std::string::npos ||
      uri.find("/.") != std::string::npos)
    return notFound();
  std::string relative = uri.substr(1);
  if (relative.empty() || relative.ends_with('/')) relative += "index.html";
  std::error_code error;
  std::filesystem::path path =
      std::filesystem::canonical(std::filesystem::path(webRoot_) / relative, error);
  if (!error && std::filesystem::is_directory(path, error))
    path = std::filesystem::canonical(path / "index.html", error);
  std::string real = path.string();
  if (error || !real.starts_with(webRoot_ + "/") ||
      !std::filesystem::is_regular_file(path, error) || error)
    return notFound();
  std::string headers;
  for (const auto& [name, value] : kSecurityHeaders)
    headers += std::string(name) + " " + value + "\r\n";
  int result = lws_serve_http_file(wsi, real.c_str(), contentType(real), headers.c_str(),
                                   int(headers.size()));
  if (result < 0 || (result > 0 && lws_http_transaction_completed(wsi))) return -1;
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
  std::optional<std::string> origin = headerValue(wsi, WSI_TOKEN_ORIGIN);
  if (!access_.originAllowed(origin, headerValue(wsi, WSI_TOKEN_HOST))) {
    sendError(*c, {ErrorCode::NotAllowed,
                   "origin '" + origin.value_or("").substr(0, 200) +
                       "' may not open sessions here: only the daemon's own pages (or the "
                       "origins in allowed_origins)",
                   "origin"});
    return closeAfterSending(*c, kClosePolicyViolation, "origin not allowed");
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
  if (const auto* pick = std::get_if<PickMessage>(&*parsed.message)) {
    auto answer = renderLoop_.pick(c.id, *pick);
    // As errors: a client that picks without reading gets no more than the queue's worth.
    if (const auto* text = std::get_if<std::string>(&answer)) {
      if (c.textOut.size() < kMaxQueuedText) sendText(c, *text);
    } else
      sendError(c, std::get<ProtocolError>(answer));
    return 0;
  }
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
  if (RenderHealth health = renderLoop_.health(); !health.ok()) {
    sendError(c, {ErrorCode::Busy,
                  "this daemon cannot render now (" +
                      (health.failure.empty() ? std::string("its render thread is stalled")
                                              : health.failure) +
                      "): try again later",
                  ""});
    closeAfterSending(c, kCloseTryAgainLater, "cannot render now");
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
  c.lastPing = c.lastPong = Clock::now();
  lws_set_timeout(wsi, NO_PENDING_TIMEOUT, 0);
  Welcome welcome = session_.welcome;
  welcome.session = std::to_string(c.id);
  welcome.limits = options_.limits;
  welcome.viewport = hello.viewport;
  welcome.lens = withSceneCameraFov(welcome.lens, session_.startCamera, hello.viewport.width,
                                    hello.viewport.height);
  SessionDefaults defaults = session_.defaults;
  defaults.lens = welcome.lens;
  sendText(c, welcomeMessage(welcome));
  renderLoop_.addSession(c.id, defaults, hello.viewport);
  metrics_.sessionStarted();
  logEvent("session_start", "session=" + std::to_string(c.id) + " peer=" + logValue(c.peer) +
                                " viewport=" + std::to_string(hello.viewport.width) + "x" +
                                std::to_string(hello.viewport.height));
  return 0;
}

int WsServer::writeNext(lws* wsi, Connection& c) {
  if (c.choked) {  // writable again: what went out has drained
    c.choked = false;
    updateSendBlocked(c);
  }
  if (c.pingDue && !c.closing) {
    c.pingDue = false;
    PingPayload payload;
    uint64_t bits = random_();
    for (char& digit : payload) {
      digit = "0123456789abcdef"[bits & 0xf];
      bits >>= 4;
    }
    c.pings.push_back(payload);
    if (c.pings.size() > 4) c.pings.pop_front();
    c.lastPing = Clock::now();
    if (!c.pingUnanswered) c.pingUnanswered = c.lastPing;
    unsigned char buffer[LWS_PRE + kPingBytes];
    std::memcpy(buffer + LWS_PRE, payload.data(), payload.size());
    if (lws_write(wsi, buffer + LWS_PRE, kPingBytes, LWS_WRITE_PING) < int(kPingBytes)) return -1;
    if (!c.textOut.empty() || c.closing || !c.framesOut.empty()) lws_callback_on_writable(wsi);
    return 0;
  }
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
  return writeFrame(wsi, c);
}

int WsServer::writeFrame(lws* wsi, Connection& c) {
  StreamFrame frame = std::move(c.framesOut.front());
  c.framesOut.pop_front();

  Clock::time_point now = Clock::now();
  const FrameRequest& request = frame.plan.request;
  FrameStatsMessage stats;
  stats.frame = frame.plan.frame;
  stats.mode = modeName(request.mode);
  stats.passesMs = frame.stats.passMs;
  stats.gpuMs = frame.stats.gpuMs;
  stats.renderMs = frame.stats.wallMs;
  stats.raysShot = frame.stats.raysShot;
  stats.maskCoverage = frame.stats.maskCoverage;
  stats.encodeMs = frame.jpeg.encodeMs;
  stats.queueWaitMs = std::max(0.0, msBetween(frame.renderedAt, now) - frame.jpeg.encodeMs);
  stats.bytes = frame.jpeg.bytes.size();
  if (frame.plan.inputReceived) stats.inputToSendMs = msBetween(*frame.plan.inputReceived, now);
  stats.jpegQuality = frame.plan.jpegQuality;
  stats.accumulatedFrames = frame.plan.accumulatedFrames;
  stats.accumulationTarget = frame.plan.accumulationTarget;
  stats.moving = frame.plan.moving;
  stats.focusDistance = request.lens.focusDistance;
  stats.renderScale = frame.plan.renderScale;
  stats.fovDeg = fieldOfViewDeg(request.lens, request.settings.width, request.settings.height);
  std::vector<uint8_t> message = frameMessage(
      {frame.plan.frame, request.settings.width, request.settings.height, frame.plan.seq},
      frameStatsJson(stats), frame.jpeg.bytes, LWS_PRE);
  size_t length = message.size() - LWS_PRE;
  if (lws_write(wsi, message.data() + LWS_PRE, length, LWS_WRITE_BINARY) < int(length)) return -1;
  ++c.framesSent;
  c.bytesSent += stats.bytes;
  metrics_.frameSent(stats.bytes, stats.encodeMs, stats.inputToSendMs);
  renderLoop_.frameSent(c.id, frame.plan.frame);
  // What did not fit into the socket waits inside libwebsockets: no more frames for this session
  // until it has drained (the next writable callback says so).
  if (lws_send_pipe_choked(wsi)) c.choked = true;
  updateSendBlocked(c);
  if (c.choked || !c.framesOut.empty() || !c.textOut.empty()) lws_callback_on_writable(wsi);
  return 0;
}

void WsServer::pong(Connection& c, const void* payload, size_t len) {
  // Only an echo of one of our pings counts: a client can send pongs without reading, but it
  // learns a ping's payload only by reading everything sent before it.
  for (const PingPayload& ping : c.pings)
    if (len == ping.size() && std::memcmp(payload, ping.data(), len) == 0) {
      c.lastPong = Clock::now();
      c.pings.clear();
      c.pingUnanswered.reset();
      if (c.unresponsive) {
        c.unresponsive = false;
        updateSendBlocked(c);
      }
      return;
    }
}

void WsServer::tick() {
  lws_sul_schedule(context_, 0, &lws_->tick.sul, Callbacks::tick, kTickUs);
  lingering_.drain();
  Clock::time_point now = Clock::now();
  auto timeout = std::chrono::milliseconds(1000 * options_.clientTimeoutS);
  auto pingEvery = std::min<Clock::duration>(timeout / 3, kPingEvery);
  int notReading = 0;
  for (auto& [id, connection] : connections_) {
    Connection& c = *connection;
    if (!c.welcomed || c.timedOut) continue;
    if (now - c.lastPong >= timeout) {
      // It has not read for client_timeout_s (even if it keeps sending): cut off, without
      // waiting for a close handshake it would not read either.
      c.timedOut = true;
      metrics_.sessionTimedOut();
      logEvent("session_timeout", "session=" + std::to_string(c.id) + " peer=" + logValue(c.peer) +
                                      " frames_waiting=" + std::to_string(c.framesOut.size()));
      lws_set_timeout(c.wsi, PENDING_TIMEOUT_USER_OK, LWS_TO_KILL_ASYNC);
      continue;
    }
    if (!c.unresponsive && c.pingUnanswered && now - *c.pingUnanswered >= kPingGrace) {
      // A reader echoes a ping within a round trip: this one has not read for a while (or is far
      // behind). No frames for it until it answers, whatever it acks.
      c.unresponsive = true;
      updateSendBlocked(c);
    }
    notReading += c.unresponsive;
    if (!c.closing && !c.pingDue && now - c.lastPing >= pingEvery) {
      c.pingDue = true;
      lws_callback_on_writable(c.wsi);
    }
  }
  metrics_.setSessionsNotReading(notReading);
}

void WsServer::dropFrame(Connection& c, const StreamFrame& frame) {
  metrics_.frameDropped();
  ++c.dropped;
  renderLoop_.frameDropped(c.id, frame.plan.frame);
}

void WsServer::updateSendBlocked(Connection& c) {
  bool blocked = c.choked || c.unresponsive ||
                 c.framesOut.size() >= std::max<size_t>(1, options_.limits.maxUnackedFrames);
  if (blocked == c.sendBlocked || !c.welcomed) return;
  c.sendBlocked = blocked;
  renderLoop_.setSendBlocked(c.id, blocked);
}

void WsServer::closed(Connection& c) {
  for (size_t i = 0; i < c.framesOut.size(); ++i) metrics_.frameDropped();
  c.dropped += c.framesOut.size();
  std::string close = c.closeCode ? std::to_string(c.closeCode) : c.timedOut ? "timeout" : "client";
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
  std::string shown = utf8Prefix(reason, kMaxCloseReason);
  lws_close_reason(wsi, lws_close_status(code), reinterpret_cast<unsigned char*>(shown.data()),
                   shown.size());
  metrics_.closed(code);
  c.closeCode = code;
  return -1;
}

}  // namespace hdof::net
