// hdof: the hybrid depth-of-field render tool and server.
#include "app/cli.h"
#include "app/commands.h"
#include "gpu/check.h"
#include "image/image.h"
#include "render/frame_pipeline.h"
#include "scene/scene.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <thread>
#include <vector>

namespace {

struct Command {
  const char* name;
  const char* summary;
  int (*run)(std::span<const std::string>);
};

const Command kCommands[] = {
    {"serve", "run the render daemon: sessions over WebSocket, the browser client over HTTP",
     hdof::runServe},
    {"load", "scripted load: N WebSocket sessions against a daemon; frames/s, latency, errors",
     hdof::runLoad},
    {"render", "render a still image or a camera path's frames in any mode (PNG or JPEG)",
     hdof::runRender},
    {"compare", "print PSNR and SSIM between two images, optionally inside a mask",
     hdof::runCompare},
    {"quality", "measure each mode against a converged ray-traced reference", hdof::runQuality},
    {"bench", "time each mode's frames and passes, lens-only and moving frames, rays/s",
     hdof::runBench},
};

// Bad usage or bad input (exit code 2), as opposed to a failure of the machine (exit code 1).
bool isInputError(const std::exception& e) {
  return dynamic_cast<const hdof::UsageError*>(&e) || dynamic_cast<const hdof::SceneError*>(&e) ||
         dynamic_cast<const hdof::ImageError*>(&e) ||
         dynamic_cast<const hdof::DeviceChoiceError*>(&e);
}

void printUsage(FILE* out) {
  std::fprintf(out,
               "usage: hdof COMMAND [OPTIONS]\n\n"
               "Hybrid depth of field: ray-traced and post-processed depth of field on Vulkan.\n\n"
               "commands:\n");
  for (const Command& c : kCommands) std::fprintf(out, "  %-10s %s\n", c.name, c.summary);
  std::fprintf(out,
               "\nRun 'hdof COMMAND --help' for a command's options.\n"
               "Scenes: a .gltf/.glb path or builtin:NAME (");
  auto names = hdof::builtinSceneNames();
  for (size_t i = 0; i < names.size(); ++i)
    std::fprintf(out, "%s%s", i ? ", " : "", names[i].c_str());
  std::fprintf(out, ").\n");
}

}  // namespace

int main(int argc, char** argv) {
  // The Vulkan loader complains on stderr when headless without a runtime directory.
  setenv("XDG_RUNTIME_DIR", "/tmp", 0);
  // Mesa's software device splits each dispatch over this many threads (default: one per core).
  // Rays cost unevenly, so twice the cores keeps every core busy to the end of a dispatch
  // (10-25% faster ray tracing measured here). GPU drivers ignore it; a set value wins.
  std::string threads = std::to_string(2 * std::max(1u, std::thread::hardware_concurrency()));
  setenv("LP_NUM_THREADS", threads.c_str(), 0);
  hdof::keepFreedMemoryForFrames();
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    printUsage(stdout);
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version") {
    std::printf("hdof 0.1.0\n");
    return 0;
  }
  for (const Command& c : kCommands) {
    if (args[0] != c.name) continue;
    try {
      return c.run(std::span<const std::string>(args).subspan(1));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "hdof %s: %s\n", c.name, e.what());
      return isInputError(e) ? 2 : 1;
    }
  }
  std::fprintf(stderr, "hdof: unknown command '%s' (see hdof --help)\n", args[0].c_str());
  return 2;
}
