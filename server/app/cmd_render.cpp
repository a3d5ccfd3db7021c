// hdof render: one still image of a scene in a given mode.
#include "app/commands.h"
#include "app/progress.h"
#include "app/scene_options.h"
#include "render/frame_pipeline.h"
#include "scene/gpu_scene.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace hdof {

int runRender(std::span<const std::string> args) {
  SceneOptions sceneOptions;
  LensOptions lensOptions;
  std::string mode = "pinhole", size = "640x360", out;
  uint32_t spp = 64;
  bool noJitter = false;
  ArgParser parser("render", "--out FILE.png|FILE.jpg [options]",
                   "Renders a still image of a scene. 'pinhole' is the sharp raster image;\n"
                   "'reference' is thin-lens ray tracing with --spp rays per pixel, the ground truth.");
  addSceneOptions(parser, sceneOptions);
  parser.option("--mode", modeNames(), "render mode (default pinhole)", &mode);
  parser.option("--spp", "N", "rays per pixel for reference (default 64)", &spp);
  parser.option("--size", "WxH", "image size in pixels (default 640x360)", &size);
  addLensOptions(parser, lensOptions);
  parser.flag("--no-pixel-jitter",
              "reference: rays through pixel centres, as the raster samples (no antialiasing)",
              &noJitter);
  parser.option("--out", "FILE", "output image, .png or .jpg (required)", &out);
  if (!parser.parse(args)) return 0;
  if (out.empty()) throw UsageError("--out FILE is required (see hdof render --help)");
  std::optional<RenderMode> renderMode = parseMode(mode);
  if (!renderMode) throw UsageError("unknown mode '" + mode + "' (modes: " + modeNames() + ")");
  Size2 imageSize = parseSize(size, 4096);
  if (spp < 1 || spp > 65536) throw UsageError("--spp must be 1 to 65536");
  std::string extension = std::filesystem::path(out).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
  if (extension != ".png" && extension != ".jpg" && extension != ".jpeg")
    throw UsageError("--out must name a .png or .jpg file (got '" + out + "')");

  LoadedScene loaded = loadSceneWithBvh(sceneOptions);
  FrameRequest request;
  request.mode = *renderMode;
  request.camera = resolveCamera(loaded.scene, sceneOptions.camera);
  request.lens = resolveLens(lensOptions, loaded, sceneOptions.camera);
  request.settings.width = imageSize.width;
  request.settings.height = imageSize.height;
  request.settings.pixelJitter = !noJitter;

  gpu::Context context(contextOptions(sceneOptions));
  GpuScene gpuScene(context, loaded.scene, loaded.bvh);
  FramePipeline pipeline(context, loaded.scene, gpuScene, imageSize.width, imageSize.height);

  double gpuMs = 0.0;
  if (request.mode == RenderMode::Reference) {
    Progress progress("reference", spp);
    gpuMs = pipeline.renderReference(request, spp, [&](uint32_t done) { progress.update(done); })
                .gpuMs;
  } else {
    gpuMs = pipeline.render(request).gpuMs;
  }
  std::error_code ignored;
  if (auto parent = std::filesystem::path(out).parent_path(); !parent.empty())
    std::filesystem::create_directories(parent, ignored);
  writeImage(out, pipeline.image());
  if (sceneOptions.verbose)
    std::fprintf(stderr, "%s %ux%u: %.1f ms on the GPU, focus %.2f m, f/%.3g at %.0f mm\n",
                 modeName(request.mode), imageSize.width, imageSize.height, gpuMs,
                 request.lens.focusDistance, request.lens.fNumber, request.lens.focalLengthMm);
  std::printf("%s\n", std::filesystem::absolute(out).c_str());
  return 0;
}

}  // namespace hdof
