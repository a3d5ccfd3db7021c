// hdof quality: each mode against a converged thin-lens reference, over the whole image, the
// partial-occlusion region and the in-focus edge band, with its frame time; and, with
// --budget-ms, each mode given the same wall-clock time on this machine.
#include "app/commands.h"
#include "app/progress.h"
#include "app/quality_motion.h"
#include "app/render_setup.h"
#include "encode/image_file.h"
#include "quality/gbuffer_geometry.h"
#include "quality/quality_regions.h"
#include "quality/reference_image.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numeric>
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
  QualityScores scores;
  double msPerFrame;
};

// One mode given one wall-clock budget.
struct BudgetRow {
  RenderMode mode;
  uint32_t raysPerPixel;  // ray-traced modes; 0 otherwise
  uint32_t budgetMs, frames;
  double elapsedMs;
  QualityScores scores;
  std::string file;  // its last frame, in the output folder
};

constexpr uint32_t kMaxBudgetMs = 60000;

// "250,1000,3000": each a whole number of milliseconds from 1 to kMaxBudgetMs.
std::vector<uint32_t> parseBudgets(const std::string& list) {
  std::vector<uint32_t> budgets;
  for (size_t start = 0; start <= list.size();) {
    size_t end = std::min(list.find(',', start), list.size());
    std::string item = list.substr(start, end - start);
    bool digits =
        !item.empty() && item.size() <= 9 &&
        std::all_of(item.begin(), item.end(), [](char c) { return c >= '0' && c <= '9'; });
    unsigned long ms = digits ? std::stoul(item) : 0;
    if (ms < 1 || ms > kMaxBudgetMs)
      throw UsageError("--budget-ms: '" + item +
                       "' is not a whole number of milliseconds from 1 to " +
                       std::to_string(kMaxBudgetMs) + " (e.g. --budget-ms 250,1000,3000)");
    budgets.push_back(uint32_t(ms));
    start = end + 1;
  }
  return budgets;
}

std::string formatDb(double db) {
  if (std::isinf(db)) return "inf";
  char text[32];
  std::snprintf(text, sizeof(text), "%.2f", db);
  return text;
}

std::string formatSsim(double ssim) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.4f", ssim);
  return text;
}

// " psnr_db=... ssim=... psnr_occl_db=... ssim_occl=... psnr_edge_db=... ssim_edge=..." ("none"
// for an empty region).
std::string formatScores(const QualityScores& s) {
  auto db = [](const std::optional<ImageComparison>& c) {
    return c ? formatDb(c->psnrDb) : std::string("none");
  };
  auto ssim = [](const std::optional<ImageComparison>& c) {
    return c ? formatSsim(c->ssim) : std::string("none");
  };
  return " psnr_db=" + formatDb(s.whole.psnrDb) + " ssim=" + formatSsim(s.whole.ssim) +
         " psnr_occl_db=" + db(s.occlusion) + " ssim_occl=" + ssim(s.occlusion) +
         " psnr_edge_db=" + db(s.edge) + " ssim_edge=" + ssim(s.edge);
}

// The same figures as JSON members (null for an empty region, or an infinite PSNR).
void addScores(nlohmann::json& out, const QualityScores& s) {
  auto db = [](double v) { return std::isinf(v) ? nlohmann::json(nullptr) : nlohmann::json(v); };
  out["psnr_db"] = db(s.whole.psnrDb);
  out["ssim"] = s.whole.ssim;
  out["psnr_occl_db"] = s.occlusion ? db(s.occlusion->psnrDb) : nullptr;
  out["ssim_occl"] = s.occlusion ? nlohmann::json(s.occlusion->ssim) : nullptr;
  out["psnr_edge_db"] = s.edge ? db(s.edge->psnrDb) : nullptr;
  out["ssim_edge"] = s.edge ? nlohmann::json(s.edge->ssim) : nullptr;
}

uint32_t raysOf(RenderMode mode, uint32_t rays) {
  return mode == RenderMode::Hybrid || mode == RenderMode::RayTrace ? rays : 0;
}

// Each mode renders the still view frame after frame from a fresh start (no history, a new
// accumulation) until `budget` ms of wall-clock time (FramePipeline::render plus the readback of
// the image, steady clock) have passed; its last frame is compared with the reference and
// written to `outDir` (MODE-BUDGETms.png). The pipelines have run before (warmUpPipelines), so
// that no first-use cost is timed.
std::vector<BudgetRow> measureBudgets(FramePipeline& pipeline, FrameRequest request,
                                      const std::vector<RenderMode>& modes, uint32_t rays,
                                      const std::vector<uint32_t>& budgets,
                                      const ImageRgba8& reference, const QualityRegions& regions,
                                      const std::filesystem::path& outDir) {
  using Clock = std::chrono::steady_clock;
  uint64_t total =
      uint64_t(std::accumulate(budgets.begin(), budgets.end(), uint64_t(0))) * modes.size();
  Progress progress("equal time", total);
  uint64_t done = 0;
  std::vector<BudgetRow> rows;
  for (RenderMode mode : modes) {
    for (uint32_t budget : budgets) {
      request.mode = mode;
      request.settings.samplesPerPixel = std::max(raysOf(mode, rays), 1u);
      request.timePasses = false;  // as the daemon renders most frames
      pipeline.resetHistory();
      pipeline.cut();
      ImageRgba8 image;
      uint32_t frames = 0;
      double elapsedMs = 0.0;
      while (elapsedMs < double(budget)) {
        request.settings.frameIndex = ++frames;
        Clock::time_point start = Clock::now();
        pipeline.render(request);
        image = pipeline.image();
        elapsedMs += std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        progress.update(done + uint64_t(std::min(elapsedMs, double(budget))));
      }
      done += budget;
      std::string file = std::string(modeName(mode)) + "-" + std::to_string(budget) + "ms.png";
      writeImage((outDir / file).string(), image);
      rows.push_back({mode, raysOf(mode, rays), budget, frames, elapsedMs,
                      scoreImage(image, reference, regions), file});
    }
  }
  return rows;
}

}  // namespace

int runQuality(std::span<const std::string> args) {
  SceneOptions sceneOptions;
  LensOptions lensOptions;
  lensOptions.fNumber = 1.4f;
  std::string size = "640x360", outDir = "out/quality";
  ReferenceOptions referenceOptions;
  std::string referencePath, modes = "pinhole,postprocess,hybrid,raytrace", cameraPathFile;
  std::string budgetList;
  uint32_t rays = 4, frames = 32;
  bool json = false;
  ArgParser parser(
      "quality", "[options]",
      "Renders a converged thin-lens reference, then each mode, and prints one line per mode:\n"
      "PSNR and SSIM against the reference over the whole image (psnr_db, ssim), over the\n"
      "partial-occlusion region (_occl: pixels within the near-field CoC of a depth edge whose\n"
      "near side is out of focus) and over the in-focus edge band (_edge: pixels within 3 px of a\n"
      "depth or normal edge whose sharper side's CoC is under 2 px, outside the occlusion "
      "region),\n"
      "and the GPU time per frame. Images and the two region masks (occlusion-mask.png,\n"
      "edge-mask.png) go to --out. For the paper's view:\n"
      "  hdof quality --scene assets/scenes/living-room/living-room.gltf --camera closeup \\\n"
      "    --focus-distance 2.4 --f-number 1.4 --focal-length 50\n"
      "With --budget-ms, each mode also gets each budget of wall-clock time on this machine from\n"
      "a fresh start, and its last frame is compared and written (MODE-BUDGETms.png). With\n"
      "--camera-path, the modes render the path's frames in motion instead, and are compared at\n"
      "four of them with references of those views (256 rays per pixel unless --reference-spp);\n"
      "a path of one keyframe is a still view, measured as a --camera is.");
  addSceneOptions(parser, sceneOptions);
  addLensOptions(parser, lensOptions);
  parser.option("--size", "WxH", "image size (default 640x360)", &size);
  parser.option("--out", "DIR", "folder for the images and the region masks (default out/quality)",
                &outDir);
  parser.option("--reference-spp", "N",
                "reference rays per pixel; default: doubled from 16 until converged, at least 256",
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
                "measure in motion along these keyframes (see hdof render --camera-path); one "
                "keyframe: that still view",
                &cameraPathFile);
  parser.option("--frames", "N", "frames along --camera-path (default 32)", &frames);
  parser.option("--budget-ms", "MS,...",
                "equal time: also render each mode for each wall-clock budget (1 to 60000 ms "
                "each, e.g. 250,1000,3000) and compare its last frame",
                &budgetList);
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
  std::vector<uint32_t> budgets;
  if (parser.given("--budget-ms")) budgets = parseBudgets(budgetList);
  std::optional<CameraPath> path;
  if (!cameraPathFile.empty()) path = loadCameraPath(cameraPathFile);
  // A path of one keyframe is a still view that the scene does not name.
  std::optional<CameraPath> still;
  if (path && path->keyframes().size() == 1) still.swap(path);
  if (path) {
    if (!budgets.empty())
      throw UsageError("--budget-ms measures a still view: it cannot go with a --camera-path of "
                       "several keyframes (one keyframe is a still view)");
    if (!referencePath.empty())
      throw UsageError("--reference is a still's reference: it cannot go with a --camera-path "
                       "of several keyframes (one keyframe is a still view)");
    if (frames < 4 || frames > 100000) throw UsageError("--frames must be 4 to 100000");
  }
  if (referenceOptions.maxRays < referenceOptions.startRays || referenceOptions.maxRays > 65536)
    throw UsageError("--max-reference-spp must be 16 to 65536");
  if (referenceOptions.fixedRays > 65536) throw UsageError("--reference-spp must be at most 65536");
  if (!(referenceOptions.targetDb > 10.0 && referenceOptions.targetDb < 100.0))
    throw UsageError("--converged-db must be between 10 and 100");

  RenderSetup setup(sceneOptions, lensOptions, imageSize);
  FrameRequest& request = setup.request;
  FramePipeline& pipeline = setup.pipeline;
  // Every mode's pipelines run once first, so that the frame times printed (and the equal-time
  // budgets) hold no compiler's time: with Mesa's shader cache empty the hybrid's first frame
  // read 9.9 s on lavapipe, now 0.11 s.
  warmUpPipelines(setup.context, setup.loaded.scene, setup.gpuScene);
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
  if (still) {
    const Camera camera = request.camera;
    const Lens lens = request.lens;
    still->sample(0.0f, camera, lens, request.camera, request.lens);
  }
  std::vector<ModeRun> runs;
  for (RenderMode mode : modeList) {
    if (mode == RenderMode::Hybrid) {
      runs.push_back({mode, rays, {1, 16}});
    } else if (mode == RenderMode::RayTrace) {
      if (rays != 1) runs.push_back({mode, 1, {1, 16}});
      runs.push_back({mode, rays, {1, 16}});
    } else {
      // The raster modes refine too while the view rests (anti-aliasing).
      runs.push_back({mode, 0, {1, 16}});
    }
  }
  auto outPath = [&](const std::string& name) {
    return (std::filesystem::path(outDir) / name).string();
  };

  // The partial-occlusion region and the in-focus edge band from the pinhole G-buffer.
  request.mode = RenderMode::Pinhole;
  pipeline.render(request);
  CocParameters coc =
      cocParameters(request.lens, imageSize.width, imageSize.height);
  QualityRegions regions = qualityRegions(readGBufferGeometry(setup.context, pipeline),
                                          imageSize.width, imageSize.height, coc);
  writeImage(outPath("occlusion-mask.png"), regions.occlusion);
  writeImage(outPath("edge-mask.png"), regions.edge);

  if (regions.occlusionPixels) referenceOptions.region = &regions.occlusion;
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
      Row row{modeName(run.mode), "", run.mode, run.raysPerPixel, frame, {}, median(frameMs)};
      char file[96];
      if (run.raysPerPixel)
        std::snprintf(file, sizeof(file), "%s-%urpp-%uf.png", row.label.c_str(), run.raysPerPixel,
                      frame);
      else
        std::snprintf(file, sizeof(file), "%s-%uf.png", row.label.c_str(), frame);
      row.file = file;
      ImageRgba8 image = pipeline.image();
      writeImage(outPath(row.file), image);
      row.scores = scoreImage(image, reference.image, regions);
      rows.push_back(row);
    }
  }
  request.settings.frameIndex = 0;
  std::vector<BudgetRow> budgetRows;
  if (!budgets.empty())
    budgetRows = measureBudgets(pipeline, request, modeList, rays, budgets, reference.image,
                                regions, outDir);

  if (json) {
    nlohmann::json out;
    if (!referencePath.empty())
      out["reference"] = {{"file", referencePath}};
    else
      out["reference"] = {{"rays_per_pixel", reference.rays},
                          {"last_step_psnr_db", reference.lastStepDb},
                          {"last_step_region_psnr_db",
                           reference.measuredRegion ? nlohmann::json(reference.lastStepRegionDb)
                                                    : nlohmann::json(nullptr)},
                          {"converged", reference.converged},
                          {"verdict", reference.verdict()}};
    out["occlusion_pixels"] = regions.occlusionPixels;
    out["edge_pixels"] = regions.edgePixels;
    out["focus_distance"] = request.lens.focusDistance;
    out["f_number"] = request.lens.fNumber;
    out["focal_length_mm"] = request.lens.focalLengthMm;
    out["sensor_mm"] = {request.lens.sensor.widthMm, request.lens.sensor.heightMm};
    glm::vec2 fov = fieldOfViewDeg(request.lens, imageSize.width, imageSize.height);
    out["fov_deg"] = {fov.x, fov.y};
    for (const Row& r : rows) {
      nlohmann::json row = {
          {"mode", r.label}, {"rays_per_pixel", r.raysPerPixel}, {"frames", r.frames}};
      addScores(row, r.scores);
      row["ms_per_frame"] = r.msPerFrame;
      row["image"] = outPath(r.file);
      out["modes"].push_back(row);
    }
    if (!budgets.empty()) {
      out["budgets"] = nlohmann::json::array();
      for (const BudgetRow& b : budgetRows) {
        nlohmann::json row = {{"mode", modeName(b.mode)},
                              {"rays_per_pixel", b.raysPerPixel},
                              {"budget_ms", b.budgetMs},
                              {"frames", b.frames},
                              {"elapsed_ms", b.elapsedMs}};
        addScores(row, b.scores);
        row["image"] = outPath(b.file);
        out["budgets"].push_back(row);
      }
    }
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
  }
  std::printf("lens: %s\n", lensSummary(request.lens, imageSize).c_str());
  std::printf("occlusion region: %llu pixels (%s)\n", (unsigned long long)regions.occlusionPixels,
              outPath("occlusion-mask.png").c_str());
  std::printf("edge band: %llu pixels (%s)\n", (unsigned long long)regions.edgePixels,
              outPath("edge-mask.png").c_str());
  for (const Row& r : rows) {
    std::printf("mode=%s", r.label.c_str());
    if (r.raysPerPixel) std::printf(" rays_per_pixel=%u", r.raysPerPixel);
    std::printf(" frames=%u", r.frames);
    std::printf("%s ms_per_frame=%.1f\n", formatScores(r.scores).c_str(), r.msPerFrame);
  }
  if (!budgets.empty()) {
    std::printf(
        "equal time: each mode renders the still view from a fresh start until the budget's "
        "wall-clock time (frames and readback) has passed; its last frame is compared\n");
    for (const BudgetRow& b : budgetRows) {
      std::printf("budget_ms=%u mode=%s", b.budgetMs, modeName(b.mode));
      if (b.raysPerPixel) std::printf(" rays_per_pixel=%u", b.raysPerPixel);
      std::printf(" frames=%u elapsed_ms=%.0f%s\n", b.frames, b.elapsedMs,
                  formatScores(b.scores).c_str());
    }
  }
  return 0;
}

}  // namespace hdof
