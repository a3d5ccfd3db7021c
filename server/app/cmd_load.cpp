// hdof load: scripted load against a running daemon (or a proxy in front of several). N real
// WebSocket sessions follow a camera path and ack frames as the browser does; prints frames/s,
// input-to-frame latency percentiles, bytes/s and errors per session and in total.
#include "app/cli.h"
#include "app/commands.h"
#include "net/load_driver.h"
#include "net/message_codec.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <regex>
#include <stdexcept>

namespace hdof {
namespace {

struct WsUrl {
  std::string host, path;
  int port = 80;
};

WsUrl parseWsUrl(const std::string& url) {
  static const std::regex form(
      R"(ws://(\[[0-9a-fA-F:.]+\]|[^/:?#\[\]]+)(:([0-9]{1,5}))?([/?][^#]*)?)");
  std::smatch match;
  if (url.starts_with("wss://"))
    throw UsageError("--url '" + url + "': wss:// is not supported (terminate TLS in the proxy)");
  if (!std::regex_match(url, match, form))
    throw UsageError("--url '" + url + "' is not a ws://HOST[:PORT][/PATH] URL");
  WsUrl parsed;
  parsed.host = match[1];
  if (parsed.host.starts_with('[')) parsed.host = parsed.host.substr(1, parsed.host.size() - 2);
  if (match[3].matched) parsed.port = std::stoi(match[3]);
  if (parsed.port < 1 || parsed.port > 65535)
    throw UsageError("--url '" + url + "': the port must be 1 to 65535");
  parsed.path = match[4].matched ? match[4].str() : "";
  if (parsed.path.empty() || parsed.path == "/") parsed.path = "/session";
  if (parsed.path.starts_with('?')) parsed.path = "/session" + parsed.path;
  return parsed;
}

struct Figures {
  uint64_t frames = 0, bytes = 0, errors = 0;
  double fps = 0.0, bytesPerSecond = 0.0, p50 = 0.0, p95 = 0.0, p99 = 0.0;
  double scaleP50 = 0.0, scaleMin = 0.0;  // frames' size over the viewport's
};

Figures figuresOf(const std::vector<net::LoadSessionResult>& results) {
  Figures f;
  std::vector<double> latencies, scales;
  for (const net::LoadSessionResult& r : results) {
    scales.insert(scales.end(), r.renderScales.begin(), r.renderScales.end());
    f.frames += r.frames;
    f.bytes += r.bytes;
    f.errors += r.errors + (r.failure.empty() ? 0 : 1);
    f.fps += r.framesPerSecond();
    f.bytesPerSecond += r.bytesPerSecond();
    latencies.insert(latencies.end(), r.latenciesMs.begin(), r.latenciesMs.end());
  }
  f.p50 = net::percentile(latencies, 0.50);
  f.p95 = net::percentile(latencies, 0.95);
  f.p99 = net::percentile(latencies, 0.99);
  f.scaleP50 = net::percentile(scales, 0.50);
  f.scaleMin = net::percentile(scales, 0.0);
  return f;
}

nlohmann::json figuresJson(const Figures& f) {
  return {{"frames", f.frames},
          {"fps", f.fps},
          {"latency_ms", {{"p50", f.p50}, {"p95", f.p95}, {"p99", f.p99}}},
          {"bytes", f.bytes},
          {"bytes_per_s", f.bytesPerSecond},
          {"render_scale", {{"p50", f.scaleP50}, {"min", f.scaleMin}}},
          {"errors", f.errors}};
}

void printFigures(const std::string& label, const Figures& f) {
  std::printf(
      "%s frames=%llu fps=%.2f latency_p50_ms=%.1f latency_p95_ms=%.1f latency_p99_ms=%.1f "
      "bytes_per_s=%.0f render_scale_p50=%.3f render_scale_min=%.3f errors=%llu",
      label.c_str(), (unsigned long long)f.frames, f.fps, f.p50, f.p95, f.p99, f.bytesPerSecond,
      f.scaleP50, f.scaleMin, (unsigned long long)f.errors);
}

}  // namespace

int runLoad(std::span<const std::string> args) {
  std::string url, cameraPathFile, size = "640x360", token;
  net::LoadOptions options;
  bool json = false;
  ArgParser parser(
      "load", "--url ws://HOST:PORT[/session] [options]",
      "Scripted load: N concurrent WebSocket sessions against hdof serve (or a proxy in front of\n"
      "several), each sending camera updates at --rate along --camera-path (the format of hdof\n"
      "render --camera-path, looped every --path-seconds; default: a sideways sway of the\n"
      "starting view) and acking every frame on receipt, as the browser client does. Prints per\n"
      "session and in total: frames/s, input-to-frame latency p50/p95/p99 (from sending a seq to\n"
      "the first frame that carries it), bytes/s, the frames' render scale (their size over the\n"
      "viewport's: lower while moving to hold the daemon's target_fps) and errors. With --still,\n"
      "more sessions hold their starting view still and take the frames that refine it; their\n"
      "figures are printed apart, and the total and fps_min_over_max are the moving sessions'.\n"
      "Exit 1 when a session failed.");
  parser.option("--url", "ws://HOST:PORT[/PATH]", "the daemon or proxy (path default /session)",
                &url);
  parser.option("--sessions", "N", "concurrent moving sessions (default 1)", &options.sessions);
  parser.option("--still", "N", "more sessions that hold their view still (default 0)",
                &options.stillSessions);
  parser.option("--duration", "S", "seconds each session runs (default 10)", &options.durationS);
  parser.option("--camera-path", "FILE.json", "keyframes the camera follows in a loop",
                &cameraPathFile);
  parser.option("--path-seconds", "S", "one loop of the camera path (default 10)",
                &options.pathSeconds);
  parser.option("--rate", "HZ", "camera updates per second and session (default 30)",
                &options.inputHz);
  parser.option("--mode", "MODE", "pinhole|postprocess|raytrace|hybrid (default: the daemon's)",
                &options.mode);
  parser.option("--size", "WxH", "viewport (default 640x360)", &size);
  parser.option("--affinity", "KEY",
                "session N adds affinity=KEY-N to its query (default: a random KEY)",
                &options.affinity);
  parser.option("--token", "TOKEN", "the daemon's access token (or HDOF_TOKEN)", &token);
  parser.flag("--json", "print one JSON object instead of lines", &json);
  if (!parser.parse(args)) return 0;

  if (url.empty()) throw UsageError("--url is required (e.g. --url ws://127.0.0.1:8080)");
  WsUrl target = parseWsUrl(url);
  options.host = target.host;
  options.port = target.port;
  options.path = target.path;
  if (options.sessions < 1 || options.sessions > 1000)
    throw UsageError("--sessions must be 1 to 1000");
  if (options.stillSessions > 1000) throw UsageError("--still must be 0 to 1000");
  if (!(options.durationS > 0.0 && options.durationS <= 86400.0))
    throw UsageError("--duration must be above 0 and at most 86400 seconds");
  if (!(options.inputHz > 0.0 && options.inputHz <= 1000.0))
    throw UsageError("--rate must be above 0 and at most 1000");
  if (!(options.pathSeconds > 0.0)) throw UsageError("--path-seconds must be above 0");
  if (!options.mode.empty() && !net::parseStreamingMode(options.mode))
    throw UsageError("--mode '" + options.mode + "': pinhole, postprocess, raytrace or hybrid");
  if (!std::regex_match(options.affinity, std::regex("[A-Za-z0-9_.-]*")))
    throw UsageError("--affinity '" + options.affinity + "': letters, digits, '_', '.', '-' only");
  Size2 viewport = parseSize(size);
  options.width = viewport.width;
  options.height = viewport.height;
  if (!cameraPathFile.empty()) {
    try {
      options.cameraPath = CameraPath::load(cameraPathFile);
    } catch (const std::exception& e) {
      throw UsageError(e.what());
    }
  }
  if (parser.given("--token"))
    options.token = token;
  else if (const char* env = std::getenv("HDOF_TOKEN"); env && *env)
    options.token = env;

  std::vector<net::LoadSessionResult> results = net::runLoad(options);
  auto failed = std::count_if(results.begin(), results.end(),
                              [](const net::LoadSessionResult& r) { return !r.completed; });
  bool noneConnected = std::none_of(results.begin(), results.end(),
                                    [](const net::LoadSessionResult& r) { return r.connected; });
  if (noneConnected) throw std::runtime_error(results.front().failure);

  std::vector<net::LoadSessionResult> moving, still;
  for (const net::LoadSessionResult& r : results) (r.still ? still : moving).push_back(r);
  Figures total = figuresOf(moving);
  double minFps = 1e300, maxFps = 0.0;
  for (const net::LoadSessionResult& r : moving) {
    minFps = std::min(minFps, r.framesPerSecond());
    maxFps = std::max(maxFps, r.framesPerSecond());
  }
  double fairness = maxFps > 0.0 ? minFps / maxFps : 0.0;
  std::string modeShown = options.mode.empty() ? "default" : options.mode;
  if (json) {
    nlohmann::json out = {{"url", url},
                          {"mode", modeShown},
                          {"size", size},
                          {"duration_s", options.durationS},
                          {"rate_hz", options.inputHz},
                          {"fps_min_over_max", fairness},
                          {"total", figuresJson(total)}};
    out["total"]["sessions"] = moving.size();
    out["total"]["failed"] = failed;
    if (!still.empty()) {
      out["still"] = figuresJson(figuresOf(still));
      out["still"]["sessions"] = still.size();
    }
    for (const net::LoadSessionResult& r : results) {
      nlohmann::json session = figuresJson(figuresOf({r}));
      session["session"] = r.index;
      session["still"] = r.still;
      session["seconds"] = r.seconds;
      session["inputs_sent"] = r.inputsSent;
      if (!r.failure.empty()) session["failure"] = r.failure;
      out["sessions"].push_back(session);
    }
    std::printf("%s\n", out.dump(2).c_str());
  } else {
    std::printf("hdof load: %zu sessions x %g s against %s, mode %s, %s, %g Hz input%s\n",
                moving.size(), options.durationS, url.c_str(), modeShown.c_str(), size.c_str(),
                options.inputHz,
                still.empty() ? "" : (", and " + std::to_string(still.size()) + " still").c_str());
    for (const net::LoadSessionResult& r : results) {
      printFigures("session=" + std::to_string(r.index) + (r.still ? " still" : ""),
                   figuresOf({r}));
      std::printf("%s%s\n", r.failure.empty() ? "" : " failure=", r.failure.c_str());
    }
    printFigures("total sessions=" + std::to_string(moving.size()), total);
    std::printf(" fps_min_over_max=%.2f\n", fairness);
    if (!still.empty()) {
      printFigures("still sessions=" + std::to_string(still.size()), figuresOf(still));
      std::printf("\n");
    }
  }
  std::fflush(stdout);
  if (failed) {
    auto first = std::find_if(results.begin(), results.end(),
                              [](const net::LoadSessionResult& r) { return !r.completed; });
    std::fprintf(stderr, "hdof load: %lld of %zu sessions failed; session %u: %s\n",
                 (long long)failed, results.size(), first->index, first->failure.c_str());
    return 1;
  }
  return 0;
}

}  // namespace hdof
