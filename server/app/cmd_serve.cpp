// hdof serve: the render daemon. One scene on one device, shared by every session; the network
// thread (this one), a render thread and a JPEG pool, wired together here. SIGINT or SIGTERM
// closes the sessions (1001) and frees the GPU resources.
#include "app/commands.h"
#include "app/render_setup.h"
#include "app/serve_config.h"
#include "encode/jpeg_pool.h"
#include "net/log.h"
#include "net/message_codec.h"
#include "net/ws_server.h"

#include <pthread.h>
#include <signal.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
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
  welcome.lens = resolveLens(LensOptions{}, loaded, "");
  net::SessionDefaults& defaults = session.defaults;
  defaults.mode = *net::parseStreamingMode(config.mode);
  defaults.stream = config.stream;
  defaults.accumulationFrames = config.accumulationFrames;
  defaults.stillAfterMs = config.stillAfterMs;
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
  options.maxSessions = config.maxSessions;
  options.limits = config.limits;
  options.clientTimeoutS = config.clientTimeoutS;
  options.helloTimeoutS = config.helloTimeoutS;
  return options;
}

}  // namespace

int runServe(std::span<const std::string> args) {
  // Every thread started from here on (the driver's too) leaves SIGINT and SIGTERM to the
  // signal thread below.
  sigset_t stopSignals;
  sigemptyset(&stopSignals);
  sigaddset(&stopSignals, SIGINT);
  sigaddset(&stopSignals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stopSignals, nullptr);

  ServeConfig flags;
  std::string configFile, origins, device;
  bool verbose = false;
  ArgParser parser(
      "serve", "[options]",
      "Runs the render daemon: the browser client at http://ADDR:PORT/, render sessions over\n"
      "WebSocket at /session (protocol/README.md), GET /healthz and GET /metrics. Every session\n"
      "renders the one scene. The access token may also come from the environment (HDOF_TOKEN).\n"
      "Flags override the config file; SIGINT or SIGTERM stops the daemon.");
  parser.option("--port", "P", "TCP port (default 8080; 0 picks a free one)", &flags.port);
  parser.option("--bind", "ADDR", "address to listen on (default 127.0.0.1; 0.0.0.0 for all)",
                &flags.bind);
  parser.option("--scene", "PATH|builtin:NAME", "the scene (default builtin:dof)", &flags.scene);
  parser.option("--config", "FILE.json", "limits and defaults (keys in README.md)", &configFile);
  parser.option("--token", "TOKEN", "sessions must send this token in hello", &flags.token);
  parser.option("--allow-origin", "O1,O2", "only WebSocket clients from these origins", &origins);
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
  if (parser.given("--token"))
    config.token = flags.token;
  else if (const char* token = std::getenv("HDOF_TOKEN"); token && *token)
    config.token = token;
  if (!std::filesystem::is_directory(config.webRoot))
    throw UsageError("the web root '" + config.webRoot + "' is not a directory (see --web-root)");
  config.webRoot = std::filesystem::absolute(config.webRoot).string();

  SceneOptions sceneOptions{config.scene, "", device, verbose};
  LoadedScene loaded = loadSceneWithBvh(sceneOptions);
  gpu::Context context(contextOptions(sceneOptions));
  GpuScene gpuScene(context, loaded.scene, loaded.bvh);

  net::Metrics metrics;
  net::RenderLoop renderLoop(context, loaded.scene, gpuScene, loaded.bvh, metrics);
  JpegPool encoders(config.encodeThreads);
  std::optional<net::WsServer> server;
  try {
    server.emplace(serverOptions(config), sessionTemplate(config, loaded, context), renderLoop,
                   metrics);
  } catch (const net::ListenError& e) {
    throw UsageError(e.what());
  }
  renderLoop.start(
      [&](net::StreamFrame frame) {
        ImageRgba8 image = std::move(frame.image);
        int quality = frame.plan.jpegQuality;
        encoders.submit(
            std::move(image), quality, [&, frame = std::move(frame)](EncodedJpeg jpeg) mutable {
              if (jpeg.bytes.empty()) {
                net::logEvent("encode_failed", "session=" + std::to_string(frame.session) +
                                                   " error=" + net::logValue(jpeg.error));
                metrics.frameDropped();
                renderLoop.frameDropped(frame.session, frame.plan.frame);
                return;
              }
              frame.jpeg = std::move(jpeg);
              server->queueFrame(std::move(frame));
            });
      },
      [&](uint64_t session, const std::string& why) { server->sessionFailed(session, why); });

  std::string host = config.bind.empty() || config.bind == "0.0.0.0" ? "localhost" : config.bind;
  std::string url = "http://" + host + ":" + std::to_string(server->port()) + "/";
  net::logEvent("listening", "url=" + url + " scene=" + net::logValue(config.scene) +
                                 " device=" + net::logValue(context.deviceName()) +
                                 " token=" + (config.token.empty() ? "no" : "yes"));
  std::printf("hdof serve: open %s (scene %s on %s; Ctrl-C stops)\n", url.c_str(),
              config.scene.c_str(), context.deviceName().c_str());
  std::fflush(stdout);

  std::atomic<bool> done{false};
  std::thread signalWaiter([&] {
    for (bool stopping = false;;) {
      int signal = 0;
      sigwait(&stopSignals, &signal);
      if (done) return;
      if (stopping) std::_Exit(130);  // a second Ctrl-C: do not wait for the clients
      stopping = true;
      net::logEvent("stopping", std::string("signal=") + (signal == SIGINT ? "SIGINT" : "SIGTERM"));
      server->stop();
    }
  });
  server->run();
  done = true;
  renderLoop.stop();    // no more frames, the pipelines freed
  encoders.shutdown();  // frames still encoding are handed to the server and dropped there
  server.reset();
  pthread_kill(signalWaiter.native_handle(), SIGTERM);
  signalWaiter.join();
  net::logEvent("stopped");
  return 0;
}

}  // namespace hdof
