#include "app/progress.h"

#include <unistd.h>

#include <cstdio>

namespace hdof {

Progress::Progress(std::string label, uint64_t total)
    : label_(std::move(label)),
      total_(total ? total : 1),
      start_(std::chrono::steady_clock::now()),
      terminal_(isatty(STDERR_FILENO) != 0) {}

Progress::~Progress() {
  if (shown_) std::fputs("\n", stderr);
}

void Progress::update(uint64_t done) {
  if (!terminal_) return;
  double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (elapsed < 1.0) return;
  shown_ = true;
  double fraction = static_cast<double>(done) / static_cast<double>(total_);
  constexpr int kWidth = 30;
  int filled = static_cast<int>(fraction * kWidth);
  double remaining = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
  std::fprintf(stderr, "\r%s [%-*s] %3d%%  %.0fs left ", label_.c_str(), kWidth,
               std::string(filled, '#').c_str(), static_cast<int>(fraction * 100.0), remaining);
  std::fflush(stderr);
}

}  // namespace hdof
