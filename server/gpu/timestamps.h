// GPU timestamps around passes: begin(cmd, name) ... end(cmd); after the command buffer has
// finished, results() gives each pass's GPU time in milliseconds, in recording order. A frame can
// go untimed: a timestamp is cheap on a GPU, but a software device finishes its queued work for
// each one (lavapipe: about 0.1 ms a pass at three stamps a pass).
#pragma once

#include "gpu/resources.h"

#include <string>
#include <utility>
#include <vector>

namespace hdof::gpu {

class GpuTimer {
 public:
  GpuTimer(const Context& context, uint32_t maxPasses = 48);
  // Starts a new frame's measurements (resets the queries; record before any begin()), or with
  // timed false a frame that writes no timestamps and whose results() are empty.
  void reset(VkCommandBuffer cmd, bool timed = true);
  void begin(VkCommandBuffer cmd, const std::string& pass);
  void end(VkCommandBuffer cmd);
  // Reads the queries written by the last finished command buffer.
  std::vector<std::pair<std::string, double>> results() const;

 private:
  const Context* context_;
  QueryPool pool_;
  uint32_t capacity_;
  std::vector<std::string> names_;
  bool enabled_;
  bool timed_ = true;
};

}  // namespace hdof::gpu
