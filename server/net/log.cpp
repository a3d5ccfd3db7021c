#include "net/log.h"

#include <chrono>
#include <cstdio>
#include <ctime>
#include <mutex>

namespace hdof::net {

void logEvent(const std::string& event, const std::string& fields) {
  static std::mutex mutex;
  auto now = std::chrono::system_clock::now();
  std::time_t seconds = std::chrono::system_clock::to_time_t(now);
  int millis = int(
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char time[32];
  std::strftime(time, sizeof(time), "%Y-%m-%dT%H:%M:%S", &utc);
  std::lock_guard lock(mutex);
  std::fprintf(stderr, "ts=%s.%03dZ event=%s%s%s\n", time, millis, event.c_str(),
               fields.empty() ? "" : " ", fields.c_str());
  std::fflush(stderr);
}

std::string logValue(const std::string& value) {
  bool bare = !value.empty();
  for (char c : value) bare = bare && c > ' ' && c != '"' && c != '=' && c != '\\' && c < 127;
  if (bare) return value;
  std::string quoted = "\"";
  for (char c : value) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += (c == '\n' || c == '\r') ? ' ' : c;
  }
  return quoted + "\"";
}

}  // namespace hdof::net
