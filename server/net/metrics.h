// The daemon's counters and timing histograms, shared by its threads, and their rendering in
// the Prometheus text format for GET /metrics.
#pragma once

#include "net/protocol.h"

#include <array>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace hdof::net {

// Cumulative bucket counts for le = each bound, in seconds.
class Histogram {
 public:
  static constexpr std::array<double, 12> kBounds = {0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025,
                                                     0.05,   0.1,   0.25,   0.5,   1.0,  2.5};
  void observe(double seconds);
  // The lines of one labelled series, e.g. labels = "pass=\"gbuffer\"" or "".
  void write(std::string& out, const std::string& name, const std::string& labels) const;

 private:
  std::array<uint64_t, kBounds.size()> counts_{};
  uint64_t count_ = 0;
  double sum_ = 0.0;
};

class Metrics {
 public:
  void sessionStarted();
  void sessionEnded();
  void frameSent(uint64_t bytes, double encodeMs, std::optional<double> inputToSendMs);
  void frameRendered(const std::vector<std::pair<std::string, double>>& passMs);
  void frameDropped();
  void sessionTimedOut();
  void setSessionsNotReading(int sessions);
  void setSessionsInteractive(int sessions);
  void inputsCoalesced(uint64_t count);
  void error(ErrorCode code);
  void closed(uint16_t closeCode);

  int activeSessions() const;
  // Frames rendered and neither sent nor dropped yet: waiting for or in the encoder, or in an
  // outgoing list.
  uint64_t framesQueued() const;
  std::string prometheusText() const;

 private:
  mutable std::mutex mutex_;
  int sessions_ = 0;
  uint64_t sessionsTotal_ = 0, frames_ = 0, bytes_ = 0, dropped_ = 0, coalesced_ = 0;
  uint64_t rendered_ = 0, timedOut_ = 0;
  int notReading_ = 0, interactive_ = 0;
  std::map<std::string, uint64_t> errors_;  // by error code
  std::map<uint16_t, uint64_t> closes_;     // by close code the daemon sent
  std::map<std::string, Histogram> passSeconds_;
  Histogram encodeSeconds_, inputToSendSeconds_;
};

}  // namespace hdof::net
