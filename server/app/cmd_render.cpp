// hdof render: a still image, or a sequence of frames along a camera path, in a given mode.
#include "app/commands.h"
#include "app/progress.h"
#include "app/render_setup.h"
#include "encode/image_file.h"
#include "render/camera_path.h"
#include "render/frame_pipeline.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <regex>

namespace hdof {
namespace {

// "frame-%04d.png" names every frame; a name without a conversion gets only the last frame.
bool isPattern(const std::string& out) { return out.find('%') != std::string::npos; }

std::string frameFileName(const std::string& pattern, uint32_t frame) {
  char name[4096];
  std::snprintf(name, sizeof(name), pattern.c_str(), frame);
  return name;
}

void checkOutputName(const std::string& out) {
  std::string extension = std::filesystem::path(out).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
  if (extension != ".png" && extension != ".jpg" && extension != ".jpeg")
    throw UsageError("--out must name a .png or .jpg file (got '" + out + "')");
  if (isPattern(out) && !std::regex_match(out, std::regex("[^%]*%0?[0-9]*d[^%]*")))
    throw UsageError("--out '" + out + "': a frame pattern holds one %d (e.g. frame-%04d.png)");
}

void writeFrame(const std::string& path, const ImageRgba8& image) {
  std::error_code ignored;
  if (auto parent = std::filesystem::path(path).parent_path(); !parent.empty())
    std::filesystem::create_directories(parent, ignored);
  writeImage(path, image);
}

}  // namespace

int runRender(std::span<const std::string> args) {
  SceneOptions sceneOptions;
  LensOptions lensOptions;
  std::string mode = "pinhole", size = "640x360", out, cameraPathFile, view = "final";
  uint32_t spp = 0, frames = 1;
  bool noJitter = false, fullMask = false;
  ArgParser parser(
      "render", "--out FILE.png|FILE.jpg [options]",
      "Renders a still image or a sequence. 'pinhole' is the sharp raster image; 'raytrace' "
      "traces\n"
      "--spp thin-lens rays per pixel each frame and accumulates them while the view is still;\n"
      "'reference' traces --spp rays per pixel for every frame, the ground truth.\n"
      "With --frames N the camera follows --camera-path (keyframes in JSON, see docs) and --out\n"
      "names every frame when it holds a %d (frame-%04d.png), else only the last one.");
  addSceneOptions(parser, sceneOptions);
  parser.option("--mode", modeNames(), "render mode (default pinhole)", &mode);
  parser.option("--spp", "N",
                "rays per pixel: reference per frame (default 64), raytrace per frame (default 1)",
                &spp);
  parser.option("--size", "WxH", "image size in pixels (default 640x360)", &size);
  addLensOptions(parser, lensOptions);
  parser.flag("--no-pixel-jitter",
              "rays and raster samples through pixel centres: no antialiasing in any mode",
              &noJitter);
  parser.option("--view", debugViewNames(), "hybrid: a debug view instead of the image", &view);
  parser.flag("--full-mask", "hybrid: trace every pixel at --spp rays, as if the mask covered all",
              &fullMask);
  parser.option("--frames", "N", "frames to render (default 1)", &frames);
  parser.option("--camera-path", "FILE.json", "keyframes the camera follows over the frames",
                &cameraPathFile);
  parser.option("--out", "FILE", "output image, .png or .jpg, or a pattern with %d (required)",
                &out);
  if (!parser.parse(args)) return 0;
  if (out.empty()) throw UsageError("--out FILE is required (see hdof render --help)");
  checkOutputName(out);
  std::optional<RenderMode> renderMode = parseMode(mode);
  if (!renderMode) throw UsageError("unknown mode '" + mode + "' (modes: " + modeNames() + ")");
  std::optional<DebugView> debugView = parseDebugView(view);
  if (!debugView) throw UsageError("unknown view '" + view + "' (views: " + debugViewNames() + ")");
  if (*debugView != DebugView::Final && *renderMode != RenderMode::Hybrid)
    throw UsageError("--view " + view + " shows a stage of the hybrid: use it with --mode hybrid");
  if (fullMask && *renderMode != RenderMode::Hybrid)
    throw UsageError("--full-mask changes the hybrid's ray mask: use it with --mode hybrid");
  if (!parser.given("--spp")) spp = *renderMode == RenderMode::Reference ? 64 : 1;
  if (spp < 1 || spp > 65536) throw UsageError("--spp must be 1 to 65536");
  if (frames < 1 || frames > 100000) throw UsageError("--frames must be 1 to 100000");
  Size2 imageSize = parseSize(size, 4096);
  std::optional<CameraPath> path;
  if (!cameraPathFile.empty()) path = loadCameraPath(cameraPathFile);

  RenderSetup setup(sceneOptions, lensOptions, imageSize);
  FrameRequest& request = setup.request;
  FramePipeline& pipeline = setup.pipeline;
  const Camera baseCamera = request.camera;
  const Lens baseLens = request.lens;
  request.mode = *renderMode;
  request.settings.pixelJitter = !noJitter;
  request.settings.samplesPerPixel = spp;
  request.view = *debugView;
  request.traceEverywhere = fullMask;

  uint64_t work = uint64_t(frames) * (request.mode == RenderMode::Reference ? spp : 1);
  Progress progress(frames > 1 ? "frames" : modeName(request.mode), work);
  double gpuMs = 0.0;
  for (uint32_t frame = 0; frame < frames; ++frame) {
    if (path)
      path->sample(frames > 1 ? float(frame) / float(frames - 1) : 0.0f, baseCamera, baseLens,
                   request.camera, request.lens);
    request.settings.frameIndex = frame;
    uint64_t done = uint64_t(frame) * (request.mode == RenderMode::Reference ? spp : 1);
    if (request.mode == RenderMode::Reference)
      gpuMs +=
          pipeline
              .renderReference(request, spp, [&](uint32_t rays) { progress.update(done + rays); })
              .gpuMs;
    else
      gpuMs += pipeline.render(request).gpuMs;
    progress.update(done + 1);
    if (isPattern(out)) writeFrame(frameFileName(out, frame), pipeline.image());
  }
  std::string written = isPattern(out) ? frameFileName(out, frames - 1) : out;
  if (!isPattern(out)) writeFrame(out, pipeline.image());
  if (sceneOptions.verbose)
    std::fprintf(stderr, "%s %ux%u, %u frame(s): %.1f ms on the GPU, lens: %s\n",
                 modeName(request.mode), imageSize.width, imageSize.height, frames, gpuMs,
                 lensSummary(request.lens, imageSize).c_str());
  std::printf("%s\n", std::filesystem::absolute(written).c_str());
  return 0;
}

}  // namespace hdof
