// Structured log lines on stderr: `ts=<UTC time> event=<name> key=value ...` (logfmt), one call
// one line, safe from any thread.
#pragma once

#include <string>

namespace hdof::net {

void logEvent(const std::string& event, const std::string& fields = "");
// A logfmt value: bare when it is a simple word, else quoted with " and \ escaped.
std::string logValue(const std::string& value);

}  // namespace hdof::net
