// hdof serve: the render daemon. One scene on one device, shared by every session; the network
// thread (this one), a render thread, a bounded encode stage in front of a JPEG pool, and a
// signal thread, wired together here. SIGINT or SIGTERM closes the sessions (1001) and frees the
// GPU resources; during start-up (scene, BVH, device) it exits at once.
#include "app/commands.h"
#include "app/render_setup.h"
#include "app/serve_config.h"
#include "encode/jpeg_pool.h"
#include "net/access_policy.h"
#include "net/frame_encoder.h"
#include "net/log.h"
#include "net/message_codec.h"
#include "net/ws_server.h"

#include <malloc.h>
#include <pthread.h>
#include <signal.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <sstream>
#include <thread>

namespace hdof {
namespace {

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) items.push_back(item);
  return items;
}

net::SessionTemplate sessionTemplate(const ServeConfig& config, const LoadedScene& loaded,
                                     const gpu::Context& context) {
  net::SessionTemplate session;
  net::Welcome& welcome = session.welcome;
  welcome.sceneName = config.scene;
  welcome.bounds = loaded.scene.bounds;
  welcome.cameras = loaded.scene.cameras;
  welcome.camera = resolveCamera(loaded.scene, "");
  // Each session's focal length follows its viewport's aspect (WsServer); this is the largest's.
  welcome.lens = resolveLens(LensOptions{}, loaded, "", {config.limits.maxWidth, config.limits.maxHeight});
  session.startCamera = loaded.scene.cameras.front();
  net::SessionDefaults& defaults = session.defaults;
  defaults.mode = *net::parseStreamingMode(config.mode);
  defaults.stream = config.stream;
  defaults.accumulationFrames = config.accumulationFrames;
  defaults.stillAfterMs = config.stillAfterMs;
  defaults.targetFps = config.targetFps;
  defaults.maxUnackedFrames = config.limits.maxUnackedFrames;
  defaults.camera = welcome.camera;
  defaults.lens = welcome.lens;
  session.sceneNames = {config.scene, loaded.scene.name};
  session.deviceName = context.deviceName();
  return session;
}

net::ServerOptions serverOptions(const ServeConfig& config) {
  net::ServerOptions options;
  options.bind = config.bind;
  options.port = int(config.port);
  options.webRoot = config.webRoot;
  options.token = config.token;
  options.allowedOrigins = config.allowedOrigins;
  options.allowedHosts = config.allowedHosts;
  options.maxSessions = config.maxSessions;
  options.limits = config.limits;
  options.clientTimeoutS = config.clientTimeoutS;
  options.helloTimeoutS = config.helloTimeoutS;
  return options;
}

// HDOF_FAULT: a fault the tests inject to see the daemon report it (docs/operations.md).
struct Faults {
  net::RenderFault render = net::RenderFault::None;
  bool slowStart = false;  // start-up takes a minute longer, as a large scene would
};

Faults injectedFaults() {
  const char* fault = std::getenv("HDOF_FAULT");
  std::string name = fault ? fault : "";
  Faults faults;
  if (name == "render-thread-exit")
    faults.render = net::RenderFault::ThreadExit;
  else if (name == "render-stall")
    faults.render = net::RenderFault::Stall;
  else if (name == "device-lost")
    faults.render = net::RenderFault::DeviceLost;
  else if (name == "slow-start")
    faults.slowStart = true;
  else if (!name.empty())
    throw UsageError("HDOF_FAULT '" + name +
                     "' is not one of render-thread-exit, render-stall, device-lost, slow-start");
  return faults;
}

// The signal thread: SIGINT and SIGTERM are blocked in every other thread and taken here. During
// start-up (nothing to close yet) the first one exits at once; while serving it stops the server
// (the sessions close with 1001); a second one, or one after serving, exits at once (130).
class StopSignals {
 public:
  explicit StopSignals(const sigset_t& signals) : signals_(signals) {
    thread_ = std::thread([this] { wait(); });
  }
  ~StopSignals() {
    {
      std::lock_guard lock(mutex_);
      state_ = State::Done;
    }
    pthread_kill(thread_.native_handle(), SIGTERM);
    thread_.join();
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  void serving(net::WsServer* server) {
    std::lock_guard lock(mutex_);
    server_ = server;
    state_ = server ? State::Serving : State::Stopping;
  }

 private:
  enum class State { Starting, Serving, Stopping, Done };
  void wait() {
    for (;;) {
      int signal = 0;
      sigwait(&signals_, &signal);
      std::lock_guard lock(mutex_);
      std::string name = signal == SIGINT ? "SIGINT" : "SIGTERM";
      switch (state_) {
        case State::Done:
          return;
        case State::Starting:
          net::logEvent("stopping", "signal=" + name + " during=start-up");
          std::_Exit(0);
        case State::Serving:
          net::logEvent("stopping", "signal=" + name);
          state_ = State::Stopping;
          server_->stop();
          break;
        case State::Stopping:
          std::_Exit(130);  // a second Ctrl-C: do not wait for the clients
      }
    }
  }

  sigset_t signals_;
  std::mutex mutex_;
  State state_ = State::Starting;
  net::WsServer* server_ = nullptr;
  std::thread thread_;
};

}  // namespace

int runServe(std::span<const std::string> args) {
  // Every thread started from here on (the driver's too) leaves SIGINT and SIGTERM to the
  // signal thread below.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  ServeConfig flags;
  std::string configFile, origins, hosts, device;
  bool verbose = false, allowInsecureToken = false;
  ArgParser parser(
      "serve", "[options]",
      "Runs the render daemon: the browser client at http://ADDR:PORT/, render sessions over\n"
      "WebSocket at /session (protocol/README.md), GET /healthz and GET /metrics. Every session\n"
      "renders the one scene. The access token may also come from the environment (HDOF_TOKEN).\n"
      "Only the daemon's own pages may open sessions unless --allow-origin lists others.\n"
      "Flags override the config file; SIGINT or SIGTERM stops the daemon.");
  parser.option("--port", "P", "TCP port (default 8080; 0 picks a free one)", &flags.port);
  parser.option("--bind", "ADDR", "address to listen on (default 127.0.0.1; 0.0.0.0 for all)",
                &flags.bind);
  parser.option("--scene", "PATH|builtin:NAME", "the scene (default builtin:dof)", &flags.scene);
  parser.option("--config", "FILE.json", "limits and defaults (keys in README.md)", &configFile);
  parser.option("--token", "TOKEN", "sessions must send this token in hello", &flags.token);
  parser.flag("--allow-insecure-token",
              "allow a token on a non-loopback address (TLS is terminated in front)",
              &allowInsecureToken);
  parser.option("--allow-origin", "O1,O2", "also WebSocket clients from these origins", &origins);
  parser.option("--allow-host", "H1,H2", "Host names to accept besides loopback ones", &hosts);
  parser.option("--web-root", "DIR", "the directory served at / (default: client_web/)",
                &flags.webRoot);
  parser.option("--device", "INDEX|NAME", "Vulkan device by index or name substring", &device);
  parser.flag("--verbose", "print the devices considered and the chosen one", &verbose);
  if (!parser.parse(args)) return 0;

  ServeConfig config = configFile.empty() ? ServeConfig{} : loadServeConfig(configFile);
  if (parser.given("--port")) {
    if (flags.port > 65535) throw UsageError("--port must be 0 to 65535");
    config.port = flags.port;
  }
  if (parser.given("--bind")) config.bind = flags.bind;
  if (parser.given("--scene")) config.scene = flags.scene;
  if (parser.given("--web-root")) config.webRoot = flags.webRoot;
  if (parser.given("--allow-origin")) config.allowedOrigins = splitList(origins);
  if (parser.given("--allow-host")) config.allowedHosts = splitList(hosts);
  if (allowInsecureToken) config.allowInsecureToken = true;
  if (parser.given("--token"))
    config.token = flags.token;
  else if (const char* token = std::getenv("HDOF_TOKEN"); token && *token)
    config.token = token;
  checkServeAccess(config);
  if (!std::filesystem::is_directory(config.webRoot))
    throw UsageError("the web root '" + config.webRoot + "' is not a directory (see --web-root)");
  config.webRoot = std::filesystem::absolute(config.webRoot).string();
  Faults faults = injectedFaults();

  // From here on a signal is taken at once: loading the scene, building the BVH and setting up
  // the device can take a while.
  StopSignals stopSignals(signals);
  if (!config.token.empty() && !net::isLoopbackBind(config.bind))
    net::logEvent("insecure_token", "bind=" + net::logValue(config.bind) + " note=" +
                                        net::logValue("the token crosses the network as sent: only "
                                                      "behind a proxy that terminates TLS"));
  if (faults.slowStart) {
    net::logEvent("fault", "name=slow-start");
    std::this_thread::sleep_for(std::chrono::seconds(60));
  }

  // Sessions reallocate their images whenever the interactive scale changes. glibc would raise
  // its mmap threshold past the size of a freed image and serve the next ones from the heap,
  // which does not shrink: fixed, every large block is mapped and goes back when freed.
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  SceneOptions sceneOptions{config.scene, "", device, verbose};
  LoadedScene loaded = loadSceneWithBvh(sceneOptions);
  gpu::Context context(contextOptions(sceneOptions));
  GpuScene gpuScene(context, loaded.scene, loaded.bvh);
  // Before listening: the first session's frames do not wait for a pipeline to compile. Said
  // first, so that a start-up does not look hung: on lavapipe (two cores) with Mesa's shader
  // cache empty it took 13-19 s, with the cache 2 s.
  net::logEvent("pipelines_warming",
                "device=" + net::logValue(context.deviceName()) + " note=" +
                    net::logValue("every mode's pipelines run once before the daemon listens "
                                  "(up to a minute on a CPU device with an empty shader cache)"));
  auto warmUpStart = std::chrono::steady_clock::now();
  warmUpPipelines(context, loaded.scene, gpuScene);
  char warmUpS[32];
  std::snprintf(
      warmUpS, sizeof(warmUpS), "%.1f",
      std::chrono::duration<double>(std::chrono::steady_clock::now() - warmUpStart).count());
  net::logEvent("pipelines_ready", "duration_s=" + std::string(warmUpS) +
                                       " programs=" + std::to_string(context.sharedObjects()));

  net::Metrics metrics;
  net::RenderLoop renderLoop(context, loaded.scene, gpuScene, loaded.bvh, metrics,
                             double(config.renderStallS), faults.render);
  JpegPool encoders(config.encodeThreads);
  std::optional<net::WsServer> server;
  try {
    server.emplace(serverOptions(config), sessionTemplate(config, loaded, context), renderLoop,
                   metrics);
  } catch (const net::ListenError& e) {
    throw UsageError(e.what());
  }
  // Frames beyond the workers wait here, at most one per session (and two per worker); past
  // that the oldest waiting frame is dropped.
  net::FrameEncoder encoder(
      [&](ImageRgba8 image, int quality, std::function<void(EncodedJpeg)> done) {
        encoders.submit(std::move(image), quality, std::move(done));
      },
      config.encodeThreads, std::max<size_t>(config.maxSessions, 2 * config.encodeThreads),
      [&](net::StreamFrame frame) {
        if (frame.jpeg.bytes.empty()) {
          net::logEvent("encode_failed", "session=" + std::to_string(frame.session) +
                                             " error=" + net::logValue(frame.jpeg.error));
          metrics.frameDropped();
          renderLoop.frameDropped(frame.session, frame.plan.frame);
          return;
        }
        server->queueFrame(std::move(frame));
      },
      [&](net::StreamFrame frame) {
        metrics.frameDropped();
        renderLoop.frameDropped(frame.session, frame.plan.frame);
      });
  renderLoop.start(
      [&](net::StreamFrame frame) { encoder.submit(std::move(frame)); },
      [&](uint64_t session, const std::string& why) { server->sessionFailed(session, why); });

  std::string host = config.bind.empty() || config.bind == "0.0.0.0" ? "localhost" : config.bind;
  std::string url = "http://" + host + ":" + std::to_string(server->port()) + "/";
  net::logEvent("listening", "url=" + url + " scene=" + net::logValue(config.scene) +
                                 " device=" + net::logValue(context.deviceName()) +
                                 " token=" + (config.token.empty() ? "no" : "yes"));
  std::printf("hdof serve: open %s (scene %s on %s; Ctrl-C stops)\n", url.c_str(),
              config.scene.c_str(), context.deviceName().c_str());
  std::fflush(stdout);

  stopSignals.serving(&*server);
  server->run();
  stopSignals.serving(nullptr);
  renderLoop.stop();    // no more frames, the pipelines freed
  encoder.shutdown();   // frames waiting for a worker are dropped
  encoders.shutdown();  // frames still encoding are handed to the server and dropped there
  server.reset();
  net::logEvent("stopped");
  return 0;
}

}  // namespace hdof
