// hdof serve's command line: bad usage and bad config are one-line errors with exit code 2,
// before anything listens.
#include "common/scratch_dir.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

struct Result {
  int exitCode = -1;
  std::string stderrText;
};

std::filesystem::path tempDir() { return hdof::test::scratchDir("serve-cli"); }

Result serve(const std::string& args) {
  auto err = tempDir() / "err.txt";
  std::string command =
      std::string(HDOF_BINARY) + " serve " + args + " >/dev/null 2>" + err.string() + " </dev/null";
  int status = std::system(command.c_str());
  std::ifstream in(err);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status),
          std::string(std::istreambuf_iterator<char>(in), {})};
}

std::string configFile(const std::string& name, const std::string& text) {
  auto path = tempDir() / name;
  std::ofstream(path) << text;
  return path.string();
}

void expectUsageError(const std::string& args, const std::string& expected) {
  Result r = serve(args);
  EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.stderrText;
  EXPECT_EQ(std::count(r.stderrText.begin(), r.stderrText.end(), '\n'), 1) << r.stderrText;
  EXPECT_NE(r.stderrText.find(expected), std::string::npos) << args << "\n" << r.stderrText;
}

TEST(ServeCli, BadUsageIsAOneLineErrorWithExitCode2) {
  expectUsageError("--port 70000", "--port");
  expectUsageError("--port abc", "abc");
  expectUsageError("--bogus", "--bogus");
  expectUsageError("--config /no/such/config.json", "/no/such/config.json");
  expectUsageError("--config " + configFile("bad.json", "{ not json"), "bad.json");
  expectUsageError("--config " + configFile("key.json", R"({"max_sesions": 2})"), "max_sesions");
  expectUsageError("--config " + configFile("type.json", R"({"max_sessions": "two"})"),
                   "max_sessions");
  expectUsageError("--config " + configFile("mode.json", R"({"mode": "reference"})"), "reference");
  expectUsageError("--config " + configFile("rays.json", R"({"rays_per_pixel": 64})"),
                   "max_rays_per_pixel");
  expectUsageError("--web-root /no/such/dir", "/no/such/dir");
  expectUsageError("--scene builtin:nope", "nope");
  // A token hello cannot carry, and a token in clear text on a non-loopback address.
  expectUsageError("--token " + std::string(257, 'x'), "at most 256");
  expectUsageError("--bind 0.0.0.0 --token s3cret", "--allow-insecure-token");
  expectUsageError("--config " + configFile("hosts.json", R"({"allowed_hosts": "a"})"),
                   "allowed_hosts");
}

TEST(ServeCli, HelpListsTheOptions) {
  std::string command = std::string(HDOF_BINARY) + " serve --help";
  FILE* pipe = popen(command.c_str(), "r");
  std::string out;
  char buffer[256];
  while (size_t n = fread(buffer, 1, sizeof(buffer), pipe)) out.append(buffer, n);
  EXPECT_EQ(pclose(pipe), 0);
  for (const char* option : {"--port", "--bind", "--scene", "--config", "--token", "--web-root",
                             "--allow-origin", "--allow-host", "--allow-insecure-token"})
    EXPECT_NE(out.find(option), std::string::npos) << option;
}

}  // namespace
