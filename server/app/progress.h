// A progress bar on stderr for long work: shown only when stderr is a terminal and the work has
// taken more than a second.
#pragma once

#include <chrono>
#include <string>

namespace hdof {

class Progress {
 public:
  Progress(std::string label, uint64_t total);
  ~Progress();
  void update(uint64_t done);

 private:
  std::string label_;
  uint64_t total_;
  std::chrono::steady_clock::time_point start_;
  bool terminal_;
  bool shown_ = false;
};

}  // namespace hdof
