// hdof quality: each mode against a converged thin-lens reference, over the whole image and over
// the partial-occlusion region, with its frame time.
#include "app/commands.h"
#include "app/progress.h"
#include "app/quality_motion.h"
#include "app/render_setup.h"
#include "encode/image_file.h"
#include "quality/occlusion_mask.h"
#include "quality/reference_image.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

namespace hdof {
namespace {

struct ModeRun {
  RenderMode mode;
  uint32_t raysPerPixel = 0;  // ray-traced modes
  std::vector<uint32_t> reportAfterFrames{1};
};

struct Row {
  std::string label, file;
  RenderMode mode;
  uint32_t raysPerPixel, frames;
  ImageComparison whole, occluded;
  double msPerFrame;
};

std::string formatDb(double db) {
  if (std::isinf(db)) return "inf";
  char text[32];
  std::snprintf(text, sizeof(text), "%.2f", db);
  return text;
}

}  // namespace

int runQuality(std::span<const std::string> args) {
  SceneOptions sceneOptions;
  LensOptions lensOptions;
  lensOptions.fNumber = 1.4f;
  std::string size = "640x360", outDir = "out/quality";
  ReferenceOptions referenceOptions;
  std::string referencePath, modes = "pinhole,postprocess,hybrid,raytrace", cameraPathFile;
  uint32_t rays = 4, frames = 32;
  bool json = false;
  ArgParser parser(
      "quality", "[options]",
      "Renders a converged thin-lens reference, then each mode, and prints one line per mode:\n"
      "PSNR and SSIM against the reference over the whole image and over the partial-occlusion\n"
      "region (pixels within the near-field CoC of a depth edge whose near side is out of focus),\n"
      "and the GPU time per frame. Images and the region mask go to --out. For the paper's view:\n"
      "  hdof quality --scene assets/scenes/living-room/living-room.gltf --camera closeup \\\n"
      "    --focus-distance 2.4 --f-number 1.4 --focal-length 50\n"
      "With --camera-path, the modes render the path's frames in motion instead, and are compared\n"
      "at four of them with references of those views (256 rays per pixel unless "
      "--reference-spp).");
  addSceneOptions(parser, sceneOptions);
  addLensOptions(parser, lensOptions);
  parser.option("--size", "WxH", "image size (default 640x360)", &size);
  parser.option("--out", "DIR", "folder for the images and the mask (default out/quality)",
                &outDir);
  parser.option("--reference-spp", "N",
                "reference rays per pixel; default: doubled from 16 until converged",
                &referenceOptions.fixedRays);
  parser.option("--max-reference-spp", "N", "most reference rays per pixel (default 1024)",
                &referenceOptions.maxRays);
  parser.option(
      "--converged-db", "DB",
      "PSNR between the reference at N and N/2 rays that counts as converged (default 42)",
      &referenceOptions.targetDb);
  parser.option("--reference", "FILE.png",
                "compare against this image (e.g. an earlier run's reference.png) instead of "
                "rendering one",
                &referencePath);
  parser.option("--modes", "LIST",
                "comma-separated modes to measure (default pinhole,postprocess,hybrid,raytrace)",
                &modes);
  parser.option("--rays", "N",
                "rays per pixel per frame of hybrid and raytrace (default 4; raytrace also at 1)",
                &rays);
  parser.option("--camera-path", "FILE.json",
                "measure in motion along these keyframes (see hdof render --camera-path)",
                &cameraPathFile);
  parser.option("--frames", "N", "frames along --camera-path (default 32)", &frames);
  parser.flag("--json", "print the results as one JSON object", &json);
  if (!parser.parse(args)) return 0;
  Size2 imageSize = parseSize(size, 4096);
  if (rays < 1 || rays > 64) throw UsageError("--rays must be 1 to 64");
  std::vector<RenderMode> modeList;
  for (size_t start = 0; start <= modes.size();) {
    size_t end = std::min(modes.find(',', start), modes.size());
    std::string name = modes.substr(start, end - start);
    std::optional<RenderMode> mode = parseMode(name);
    if (!mode || *mode == RenderMode::Reference)
      throw UsageError("--modes: unknown mode '" + name +
                       "'; use pinhole, postprocess, hybrid or raytrace");
    modeList.push_back(*mode);
    start = end + 1;
  }
  std::optional<CameraPath> path;
  if (!cameraPathFile.empty()) {
    if (!referencePath.empty())
      throw UsageError("--reference is a still's reference: it cannot go with --camera-path");
    if (frames < 4 || frames > 100000) throw UsageError("--frames must be 4 to 100000");
    path = loadCameraPath(cameraPathFile);
  }
  if (referenceOptions.maxRays < referenceOptions.startRays || referenceOptions.maxRays > 65536)
    throw UsageError("--max-reference-spp must be 16 to 65536");
  if (referenceOptions.fixedRays > 65536) throw UsageError("--reference-spp must be at most 65536");
  if (!(referenceOptions.targetDb > 10.0 && referenceOptions.targetDb < 100.0))
    throw UsageError("--converged-db must be between 10 and 100");

  RenderSetup setup(sceneOptions, lensOptions, imageSize);
  FrameRequest& request = setup.request;
  FramePipeline& pipeline = setup.pipeline;
  std::filesystem::create_directories(outDir);
  if (path) {
    MotionQualityOptions motion;
    motion.frames = frames;
    motion.referenceRays = referenceOptions.fixedRays ? referenceOptions.fixedRays : 256;
    motion.raysPerPixel = rays;
    motion.modes = modeList;
    motion.outDir = outDir;
    motion.json = json;
    measureQualityInMotion(setup, *path, motion);
    return 0;
  }
  std::vector<ModeRun> runs;
  for (RenderMode mode : modeList) {
    if (mode == RenderMode::Hybrid) {
      runs.push_back({mode, rays, {1, 16}});
    } else if (mode == RenderMode::RayTrace) {
      if (rays != 1) runs.push_back({mode, 1, {1, 16}});
      runs.push_back({mode, rays, {1, 16}});
    } else {
      runs.push_back({mode});
    }
  }
  auto outPath = [&](const std::string& name) {
    return (std::filesystem::path(outDir) / name).string();
  };

  // The partial-occlusion region from the pinhole depth.
  request.mode = RenderMode::Pinhole;
  pipeline.render(request);
  CocParameters coc =
      cocParameters(request.camera, request.lens, imageSize.width, imageSize.height);
  std::vector<uint8_t> region =
      occlusionMask(pipeline.linearDepth(), imageSize.width, imageSize.height, coc);
  ImageRgba8 regionImage = maskImage(region, imageSize.width, imageSize.height);
  writeImage(outPath("occlusion-mask.png"), regionImage);
  bool hasRegion = maskCount(region) > 0;

  if (hasRegion) referenceOptions.region = &regionImage;
  ReferenceImage reference;
  if (!referencePath.empty()) {
    reference.image = readImage(referencePath);
    if (reference.image.width != imageSize.width || reference.image.height != imageSize.height)
      throw UsageError("--reference: " + referencePath + " is " +
                       std::to_string(reference.image.width) + "x" +
                       std::to_string(reference.image.height) + ", not the --size " + size);
  } else {
    Progress progress("reference", referenceOptions.fixedRays ? referenceOptions.fixedRays
                                                              : referenceOptions.maxRays);
    reference = renderConvergedReference(pipeline, request, referenceOptions,
                                         [&](uint32_t rays) { progress.update(rays); });
  }
  if (referencePath.empty()) {
    writeImage(outPath("reference.png"), reference.image);
    if (!json) std::printf("reference: %s\n", reference.verdict().c_str());
  }

  std::vector<Row> rows;
  for (const ModeRun& run : runs) {
    request.mode = run.mode;
    request.settings.samplesPerPixel = std::max(run.raysPerPixel, 1u);
    pipeline.resetHistory();
    uint32_t lastFrame = run.reportAfterFrames.back();
    std::vector<double> frameMs;
    for (uint32_t frame = 1; frame <= lastFrame; ++frame) {
      request.settings.frameIndex = frame;
      frameMs.push_back(pipeline.render(request).gpuMs);
      if (std::find(run.reportAfterFrames.begin(), run.reportAfterFrames.end(), frame) ==
          run.reportAfterFrames.end())
        continue;
      Row row{modeName(run.mode), "", run.mode, run.raysPerPixel, frame, {}, {}, median(frameMs)};
      char file[96];
      if (run.raysPerPixel)
        std::snprintf(file, sizeof(file), "%s-%urpp-%uf.png", row.label.c_str(), run.raysPerPixel,
                      frame);
      else
        std::snprintf(file, sizeof(file), "%s.png", row.label.c_str());
      row.file = file;
      ImageRgba8 image = pipeline.image();
      writeImage(outPath(row.file), image);
      row.whole = compareImages(image, reference.image);
      if (hasRegion) row.occluded = compareImages(image, reference.image, &regionImage);
      rows.push_back(row);
    }
  }

  if (json) {
    nlohmann::json out;
    if (!referencePath.empty())
      out["reference"] = {{"file", referencePath}};
    else
      out["reference"] = {{"rays_per_pixel", reference.rays},
                          {"last_step_psnr_db", reference.lastStepDb},
                          {"last_step_region_psnr_db", reference.lastStepRegionDb},
                          {"converged", reference.converged},
                          {"verdict", reference.verdict()}};
    out["occlusion_pixels"] = maskCount(region);
    out["focus_distance"] = request.lens.focusDistance;
    out["f_number"] = request.lens.fNumber;
    out["focal_length_mm"] = request.lens.focalLengthMm;
    for (const Row& r : rows) {
      auto db = [](double v) {
        return std::isinf(v) ? nlohmann::json(nullptr) : nlohmann::json(v);
      };
      out["modes"].push_back({{"mode", r.label},
                              {"rays_per_pixel", r.raysPerPixel},
                              {"frames", r.frames},
                              {"psnr_db", db(r.whole.psnrDb)},
                              {"ssim", r.whole.ssim},
                              {"psnr_occl_db", hasRegion ? db(r.occluded.psnrDb) : nullptr},
                              {"ssim_occl", hasRegion ? nlohmann::json(r.occluded.ssim) : nullptr},
                              {"ms_per_frame", r.msPerFrame},
                              {"image", outPath(r.file)}});
    }
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
  }
  std::printf("occlusion region: %llu pixels (%s)\n", (unsigned long long)maskCount(region),
              outPath("occlusion-mask.png").c_str());
  for (const Row& r : rows) {
    std::printf("mode=%s", r.label.c_str());
    if (r.raysPerPixel) std::printf(" rays_per_pixel=%u frames=%u", r.raysPerPixel, r.frames);
    std::printf(" psnr_db=%s ssim=%.4f psnr_occl_db=%s ssim_occl=%s ms_per_frame=%.1f\n",
                formatDb(r.whole.psnrDb).c_str(), r.whole.ssim,
                hasRegion ? formatDb(r.occluded.psnrDb).c_str() : "none",
                hasRegion ? std::to_string(r.occluded.ssim).substr(0, 6).c_str() : "none",
                r.msPerFrame);
  }
  return 0;
}

}  // namespace hdof
