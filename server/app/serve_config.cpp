#include "app/serve_config.h"

#include "app/cli.h"
#include "net/access_policy.h"
#include "net/message_codec.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <functional>
#include <map>
#include <sstream>

namespace hdof {
namespace {

using nlohmann::json;

struct Reader {
  std::string source;
  std::string where(const std::string& key) const { return source + ": '" + key + "'"; }

  uint32_t count(const json& value, const std::string& key, uint32_t min, uint32_t max) const {
    if (!value.is_number_integer() || value.get<int64_t>() < min || value.get<int64_t>() > max)
      throw UsageError(where(key) + " must be a whole number from " + std::to_string(min) + " to " +
                       std::to_string(max));
    return value.get<uint32_t>();
  }
  double number(const json& value, const std::string& key, double min, double max) const {
    if (!value.is_number() || value.get<double>() < min || value.get<double>() > max)
      throw UsageError(where(key) + " must be a number from " + json(min).dump() + " to " +
                       json(max).dump());
    return value.get<double>();
  }
  std::string text(const json& value, const std::string& key) const {
    if (!value.is_string()) throw UsageError(where(key) + " must be a string");
    return value.get<std::string>();
  }
};

}  // namespace

ServeConfig parseServeConfig(const std::string& text, const std::string& source, ServeConfig c) {
  json object = json::parse(text, nullptr, false);
  if (object.is_discarded() || !object.is_object())
    throw UsageError(source + " is not a JSON object (see the config keys in README.md)");
  Reader r{source};
  using Setter = std::function<void(const json&, const std::string&)>;
  auto count = [&](uint32_t* out, uint32_t min, uint32_t max) -> Setter {
    return [=, &r](const json& v, const std::string& k) { *out = r.count(v, k, min, max); };
  };
  net::Limits& limits = c.limits;
  const std::map<std::string, Setter> keys = {
      {"bind", [&](const json& v, const std::string& k) { c.bind = r.text(v, k); }},
      {"port", count(&c.port, 0, 65535)},
      {"scene", [&](const json& v, const std::string& k) { c.scene = r.text(v, k); }},
      {"web_root", [&](const json& v, const std::string& k) { c.webRoot = r.text(v, k); }},
      {"token", [&](const json& v, const std::string& k) { c.token = r.text(v, k); }},
      {"allowed_origins",
       [&](const json& v, const std::string& k) {
         if (!v.is_array()) throw UsageError(r.where(k) + " must be a list of origins");
         c.allowedOrigins.clear();
         for (const json& origin : v) c.allowedOrigins.push_back(r.text(origin, k));
       }},
      {"allowed_hosts",
       [&](const json& v, const std::string& k) {
         if (!v.is_array()) throw UsageError(r.where(k) + " must be a list of host names");
         c.allowedHosts.clear();
         for (const json& host : v) c.allowedHosts.push_back(r.text(host, k));
       }},
      {"allow_insecure_token",
       [&](const json& v, const std::string& k) {
         if (!v.is_boolean()) throw UsageError(r.where(k) + " must be true or false");
         c.allowInsecureToken = v.get<bool>();
       }},
      {"max_sessions", count(&c.maxSessions, 1, 1024)},
      {"max_width", count(&limits.maxWidth, 16, 8192)},
      {"max_height", count(&limits.maxHeight, 16, 8192)},
      {"max_rays_per_pixel", count(&limits.maxRaysPerPixel, 1, 1024)},
      {"max_message_bytes", count(&limits.maxMessageBytes, 256, 1 << 20)},
      {"max_unacked_frames", count(&limits.maxUnackedFrames, 1, 16)},
      {"client_timeout_s", count(&c.clientTimeoutS, 2, 3600)},
      {"hello_timeout_s", count(&c.helloTimeoutS, 1, 3600)},
      {"encode_threads", count(&c.encodeThreads, 1, 64)},
      {"render_stall_s", count(&c.renderStallS, 1, 3600)},
      {"mode", [&](const json& v, const std::string& k) { c.mode = r.text(v, k); }},
      {"jpeg_quality_moving",
       [&](const json& v, const std::string& k) {
         c.stream.jpegQualityMoving = int(r.count(v, k, 1, 100));
       }},
      {"jpeg_quality_still",
       [&](const json& v, const std::string& k) {
         c.stream.jpegQualityStill = int(r.count(v, k, 1, 100));
       }},
      {"max_fps",
       [&](const json& v, const std::string& k) { c.stream.maxFps = r.number(v, k, 1, 240); }},
      {"rays_per_pixel", count(&c.stream.raysPerPixel, 1, 1024)},
      {"accumulation_frames", count(&c.accumulationFrames, 1, 100000)},
      {"still_after_ms",
       [&](const json& v, const std::string& k) { c.stillAfterMs = r.number(v, k, 0, 10000); }},
      {"target_fps",
       [&](const json& v, const std::string& k) { c.targetFps = r.number(v, k, 0, 240); }},
  };
  for (const auto& [key, value] : object.items()) {
    auto it = keys.find(key);
    if (it == keys.end()) throw UsageError(source + ": unknown key '" + key + "' (see README.md)");
    it->second(value, key);
  }
  checkServeConfig(c, source);
  return c;
}

void checkServeConfig(const ServeConfig& c, const std::string& source) {
  if (!net::parseStreamingMode(c.mode))
    throw UsageError(source + ": mode '" + c.mode +
                     "' is not one of pinhole, postprocess, raytrace, hybrid");
  if (c.stream.raysPerPixel > c.limits.maxRaysPerPixel)
    throw UsageError(source + ": rays_per_pixel " + std::to_string(c.stream.raysPerPixel) +
                     " is more than max_rays_per_pixel " +
                     std::to_string(c.limits.maxRaysPerPixel));
}

void checkServeAccess(const ServeConfig& c) {
  if (c.token.size() > net::kMaxTokenBytes)
    throw UsageError("the token is " + std::to_string(c.token.size()) +
                     " bytes: hello carries at most " + std::to_string(net::kMaxTokenBytes) +
                     ", so no client could ever send it");
  if (!c.token.empty() && !net::isLoopbackBind(c.bind) && !c.allowInsecureToken)
    throw UsageError("a token on " + (c.bind.empty() ? std::string("every interface") : c.bind) +
                     " would cross the network in clear text: put a TLS proxy in front "
                     "(docs/operations.md) and pass --allow-insecure-token "
                     "(\"allow_insecure_token\": true)");
}

ServeConfig loadServeConfig(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw UsageError("cannot read the config file '" + path + "'");
  std::stringstream text;
  text << in.rdbuf();
  return parseServeConfig(text.str(), "config " + path);
}

}  // namespace hdof
