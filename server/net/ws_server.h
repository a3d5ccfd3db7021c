// The daemon's network side: one libwebsockets context on one port that serves client_web/ over
// HTTP (GET and HEAD; files only inside the web root), GET /healthz and /metrics, and render
// sessions over WebSocket at /session (subprotocol hdof.v1; every other upgrade gets an HTTP
// error). Who may connect: net/access_policy.h. Only run()'s thread touches libwebsockets; it
// does I/O and message validation, never rendering or encoding. Other threads hand it frames and
// failures through a locked inbox and wake it with lws_cancel_service.
//
// Flow control: a session's frames go out one at a time when its socket is writable; while the
// socket is choked or its outgoing list holds max_unacked_frames frames the render loop does not
// schedule it (RenderLoop::setSendBlocked), and the list never holds more (the oldest is dropped).
// Acks count only for frames written. Every welcomed session is pinged with a random payload
// every 2 s (client_timeout_s / 3 when shorter), which only a client that reads what came before
// can echo: one that leaves a ping unanswered for a second is not scheduled until it answers, and
// one that has echoed none for client_timeout_s is cut off. A session's socket lingers after
// its close (net/lingering_close.h).
#pragma once

#include "net/access_policy.h"
#include "net/lingering_close.h"
#include "net/metrics.h"
#include "net/render_loop.h"
#include "net/server_messages.h"

#include <atomic>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

struct lws;
struct lws_context;

namespace hdof::net {

struct ServerOptions {
  std::string bind = "127.0.0.1";           // address (or interface) to listen on; empty: all
  int port = 8080;                          // 0: any free port (see port())
  std::string webRoot;                      // the directory served at /
  std::string token;                        // when set, hello must carry it
  std::vector<std::string> allowedOrigins;  // when set, the WebSocket Origin must be one of them
  std::vector<std::string> allowedHosts;    // Host names accepted besides loopback ones
  uint32_t maxSessions = 8;
  Limits limits;
  uint32_t clientTimeoutS = 30;  // no pong to our pings for this long: the client is cut off
  uint32_t helloTimeoutS = 10;   // no hello this long after connecting: closed
};

// The daemon cannot listen where it was asked to.
struct ListenError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// What every session's welcome shares (the session id and limits are filled in per session).
struct SessionTemplate {
  Welcome welcome;
  SessionDefaults defaults;
  // The scene camera of the starting view: each session's starting focal length is the one that
  // frames as it does at the session's viewport (on the starting lens's sensor).
  SceneCamera startCamera;
  std::vector<std::string> sceneNames;  // what hello.scene may say
  std::string deviceName;
};

class WsServer {
 public:
  // Listens at once; throws ListenError when it cannot (address in use, not this machine's).
  WsServer(const ServerOptions& options, SessionTemplate session, RenderLoop& renderLoop,
           Metrics& metrics);
  ~WsServer();
  WsServer(const WsServer&) = delete;
  WsServer& operator=(const WsServer&) = delete;

  int port() const { return port_; }
  // Serves until stop() and then until every session is closed (at most 2 s more).
  void run();

  // Any thread:
  void stop();
  void queueFrame(StreamFrame frame);
  void sessionFailed(uint64_t session, const std::string& why);

  struct Connection;  // one WebSocket, on run()'s thread only

 private:
  // libwebsockets' callbacks: 0 to go on, -1 to close the connection (1 to refuse an upgrade);
  // onHttp returns nothing for what libwebsockets' default handling does.
  int onSession(lws* wsi, int reason, Connection*& slot, void* in, size_t len);
  std::optional<int> onHttp(lws* wsi, int reason, void* in);
  friend struct Callbacks;

  int httpRequest(lws* wsi);
  int confirmUpgrade(lws* wsi, const char* upgrade);
  int serveFile(lws* wsi, const std::string& uri);
  int healthz(lws* wsi, bool head);
  void tick();  // four times a second: pings, cut-offs

  void open(lws* wsi, Connection*& slot);
  int receive(lws* wsi, Connection& c, const char* data, size_t len);
  int handleMessage(lws* wsi, Connection& c, const std::string& text);
  int hello(lws* wsi, Connection& c, const HelloMessage& hello);
  int writeNext(lws* wsi, Connection& c);
  int writeFrame(lws* wsi, Connection& c);
  void pong(Connection& c, const void* payload, size_t len);
  void dropFrame(Connection& c, const StreamFrame& frame);
  void updateSendBlocked(Connection& c);
  void closed(Connection& c);
  void takeInbox();

  void sendError(Connection& c, const ProtocolError& error);
  void sendText(Connection& c, std::string text);
  void closeAfterSending(Connection& c, uint16_t code, const std::string& reason);
  int closeNow(lws* wsi, Connection& c, uint16_t code, const std::string& reason);

  ServerOptions options_;
  AccessPolicy access_;
  std::string webRoot_;  // the web root's real path (symlinks resolved)
  SessionTemplate session_;
  RenderLoop& renderLoop_;
  Metrics& metrics_;
  lws_context* context_ = nullptr;
  int port_ = 0;
  LingeringClose lingering_;

  std::map<uint64_t, Connection*> connections_;
  uint64_t nextId_ = 1;
  int welcomed_ = 0;
  bool stopping_ = false;
  bool shutdownDeadline_ = false;
  struct LwsSetup;  // what the context points into: protocols, timers
  std::unique_ptr<LwsSetup> lws_;
  std::mt19937_64 random_;  // ping payloads

  std::mutex inboxMutex_;
  std::vector<StreamFrame> inboxFrames_;
  std::vector<std::pair<uint64_t, std::string>> inboxFailures_;
  std::atomic<bool> stopRequested_{false};
};

}  // namespace hdof::net
