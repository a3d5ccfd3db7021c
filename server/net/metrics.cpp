#include "net/metrics.h"

#include <algorithm>
#include <cstdio>

namespace hdof::net {
namespace {

std::string format(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.9g", value);
  return text;
}

void header(std::string& out, const char* name, const char* type, const char* help) {
  out += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n";
}

void sample(std::string& out, const std::string& name, const std::string& labels, double value) {
  out += name + (labels.empty() ? "" : "{" + labels + "}") + " " + format(value) + "\n";
}

}  // namespace

void Histogram::observe(double seconds) {
  for (size_t i = 0; i < kBounds.size(); ++i)
    if (seconds <= kBounds[i]) ++counts_[i];
  ++count_;
  sum_ += seconds;
}

void Histogram::write(std::string& out, const std::string& name, const std::string& labels) const {
  std::string prefix = labels.empty() ? "" : labels + ",";
  for (size_t i = 0; i < kBounds.size(); ++i)
    sample(out, name + "_bucket", prefix + "le=\"" + format(kBounds[i]) + "\"", double(counts_[i]));
  sample(out, name + "_bucket", prefix + "le=\"+Inf\"", double(count_));
  sample(out, name + "_sum", labels, sum_);
  sample(out, name + "_count", labels, double(count_));
}

void Metrics::sessionStarted() {
  std::lock_guard lock(mutex_);
  ++sessions_;
  ++sessionsTotal_;
}

void Metrics::sessionEnded() {
  std::lock_guard lock(mutex_);
  --sessions_;
}

void Metrics::frameSent(uint64_t bytes, double encodeMs, std::optional<double> inputToSendMs) {
  std::lock_guard lock(mutex_);
  ++frames_;
  bytes_ += bytes;
  encodeSeconds_.observe(encodeMs * 1e-3);
  if (inputToSendMs) inputToSendSeconds_.observe(*inputToSendMs * 1e-3);
}

void Metrics::frameRendered(const std::vector<std::pair<std::string, double>>& passMs) {
  std::lock_guard lock(mutex_);
  ++rendered_;
  for (const auto& [pass, ms] : passMs) passSeconds_[pass].observe(ms * 1e-3);
}

void Metrics::frameDropped() {
  std::lock_guard lock(mutex_);
  ++dropped_;
}

void Metrics::sessionTimedOut() {
  std::lock_guard lock(mutex_);
  ++timedOut_;
}

void Metrics::setSessionsNotReading(int sessions) {
  std::lock_guard lock(mutex_);
  notReading_ = sessions;
}

void Metrics::setSessionsInteractive(int sessions) {
  std::lock_guard lock(mutex_);
  interactive_ = sessions;
}

void Metrics::inputsCoalesced(uint64_t count) {
  std::lock_guard lock(mutex_);
  coalesced_ += count;
}

void Metrics::error(ErrorCode code) {
  std::lock_guard lock(mutex_);
  ++errors_[errorCodeName(code)];
}

void Metrics::closed(uint16_t closeCode) {
  std::lock_guard lock(mutex_);
  ++closes_[closeCode];
}

int Metrics::activeSessions() const {
  std::lock_guard lock(mutex_);
  return sessions_;
}

uint64_t Metrics::framesQueued() const {
  std::lock_guard lock(mutex_);
  return rendered_ - std::min(rendered_, frames_ + dropped_);
}

std::string Metrics::prometheusText() const {
  std::lock_guard lock(mutex_);
  std::string out;
  header(out, "hdof_sessions", "gauge", "Sessions open now.");
  sample(out, "hdof_sessions", "", sessions_);
  header(out, "hdof_sessions_total", "counter", "Sessions started.");
  sample(out, "hdof_sessions_total", "", double(sessionsTotal_));
  header(out, "hdof_sessions_timed_out_total", "counter",
         "Sessions cut off for answering no ping for client_timeout_s (not reading).");
  sample(out, "hdof_sessions_timed_out_total", "", double(timedOut_));
  header(out, "hdof_sessions_not_reading", "gauge",
         "Sessions paused: a ping of theirs has gone unanswered for a second.");
  sample(out, "hdof_sessions_not_reading", "", notReading_);
  header(out, "hdof_sessions_interactive", "gauge",
         "Sessions whose frames answer input now; the others' refining frames wait for them.");
  sample(out, "hdof_sessions_interactive", "", interactive_);
  header(out, "hdof_frames_rendered_total", "counter", "Frames rendered.");
  sample(out, "hdof_frames_rendered_total", "", double(rendered_));
  header(out, "hdof_frames_queued", "gauge",
         "Frames rendered and not yet sent or dropped (encoding, or waiting to be written).");
  sample(out, "hdof_frames_queued", "",
         double(rendered_ - std::min(rendered_, frames_ + dropped_)));
  header(out, "hdof_frames_sent_total", "counter", "Frames sent to clients.");
  sample(out, "hdof_frames_sent_total", "", double(frames_));
  header(out, "hdof_bytes_sent_total", "counter", "JPEG bytes sent to clients.");
  sample(out, "hdof_bytes_sent_total", "", double(bytes_));
  header(out, "hdof_frames_dropped_total", "counter",
         "Frames rendered but never sent (the session ended, the encode failed, or a bounded "
         "queue dropped its oldest).");
  sample(out, "hdof_frames_dropped_total", "", double(dropped_));
  header(out, "hdof_inputs_coalesced_total", "counter",
         "Camera and lens updates replaced by a newer one before they were rendered.");
  sample(out, "hdof_inputs_coalesced_total", "", double(coalesced_));
  header(out, "hdof_errors_total", "counter", "Error messages sent, by code.");
  for (const auto& [code, count] : errors_)
    sample(out, "hdof_errors_total", "code=\"" + code + "\"", double(count));
  header(out, "hdof_closes_total", "counter", "Sessions the daemon closed, by close code.");
  for (const auto& [code, count] : closes_)
    sample(out, "hdof_closes_total", "code=\"" + std::to_string(code) + "\"", double(count));
  header(out, "hdof_pass_seconds", "histogram",
         "GPU time of each render pass, of timed frames (one in 8 of a session's).");
  for (const auto& [pass, histogram] : passSeconds_)
    histogram.write(out, "hdof_pass_seconds", "pass=\"" + pass + "\"");
  header(out, "hdof_encode_seconds", "histogram", "JPEG encode time per frame.");
  encodeSeconds_.write(out, "hdof_encode_seconds", "");
  header(out, "hdof_input_to_send_seconds", "histogram",
         "From receiving an input to sending the frame that applies it.");
  inputToSendSeconds_.write(out, "hdof_input_to_send_seconds", "");
  return out;
}

}  // namespace hdof::net
