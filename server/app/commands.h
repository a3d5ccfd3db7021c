// The subcommands of `hdof`. Each takes its arguments (after the command name) and returns the
// process exit code; UsageError (exit 2) and other exceptions are reported by main().
#pragma once

#include <span>
#include <string>

namespace hdof {

int runRender(std::span<const std::string> args);
int runCompare(std::span<const std::string> args);
int runBench(std::span<const std::string> args);
int runQuality(std::span<const std::string> args);
int runServe(std::span<const std::string> args);
int runLoad(std::span<const std::string> args);

}  // namespace hdof
