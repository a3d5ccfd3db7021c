// A test process's folder for the files its tests write (configs, daemon logs, captured output):
// one per process and name under the system's temporary directory, removed when the process
// ends with every test passed, and kept after a failure for what its files say.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

namespace hdof::test {

namespace detail {
class ScratchDirs {
 public:
  // gtest's singleton is made first, so that it is still there when this one is destroyed.
  ScratchDirs() : unitTest_(testing::UnitTest::GetInstance()) {}
  ~ScratchDirs() {
    if (!unitTest_->Passed()) return;
    std::error_code ignored;
    for (const auto& dir : dirs_) std::filesystem::remove_all(dir, ignored);
  }
  std::filesystem::path get(const std::string& name) {
    auto dir = std::filesystem::temp_directory_path() /
               ("hdof-" + name + "-" + std::to_string(getpid()));
    std::lock_guard lock(mutex_);
    if (std::find(dirs_.begin(), dirs_.end(), dir) == dirs_.end()) {
      std::filesystem::create_directories(dir);
      dirs_.push_back(dir);
    }
    return dir;
  }

 private:
  testing::UnitTest* unitTest_;
  std::mutex mutex_;
  std::vector<std::filesystem::path> dirs_;
};
}  // namespace detail

// /tmp/hdof-NAME-PID, made on first use.
inline std::filesystem::path scratchDir(const std::string& name) {
  static detail::ScratchDirs dirs;
  return dirs.get(name);
}

}  // namespace hdof::test
