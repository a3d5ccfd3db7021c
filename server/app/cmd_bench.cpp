// hdof bench: the speed figures of the foundation: BVH build, G-buffer, ray traversal.
#include "app/commands.h"
#include "app/render_setup.h"
#include "render/frame_pipeline.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace hdof {
namespace {

// Milliseconds to three significant digits or more: a GPU's frames take a millisecond or two
// and its passes hundredths of one, which a fixed decimal or two would print as 1.3 or 0.01.
std::string msText(double ms) {
  int decimals = ms > 0.0 ? std::clamp(2 - int(std::floor(std::log10(ms))), 1, 6) : 1;
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", decimals, ms);
  return text;
}

// Each pass's times over several frames, in the order the passes first ran.
class PassTimes {
 public:
  void add(const FrameStats& stats) {
    for (const auto& [pass, ms] : stats.passMs) {
      auto it = std::find_if(passes_.begin(), passes_.end(),
                             [&name = pass](const auto& entry) { return entry.first == name; });
      if (it == passes_.end()) it = passes_.insert(passes_.end(), {pass, {}});
      it->second.push_back(ms);
    }
  }
  double medianOf(const std::string& pass) const {
    for (const auto& [name, times] : passes_)
      if (name == pass) return median(times);
    return 0.0;
  }
  // " pass=ms" words, or "\"pass\":ms" members of a JSON object; medians.
  std::string text(bool json) const {
    std::string out;
    for (const auto& [pass, times] : passes_) {
      char entry[96];
      if (json)
        std::snprintf(entry, sizeof entry, "%s\"%s\":%.3f", out.empty() ? "" : ",", pass.c_str(),
                      median(times));
      else
        std::snprintf(entry, sizeof entry, " %s=%s", pass.c_str(), msText(median(times)).c_str());
      out += entry;
    }
    return out;
  }

 private:
  std::vector<std::pair<std::string, std::vector<double>>> passes_;
};

}  // namespace

int runBench(std::span<const std::string> args) {
  SceneOptions sceneOptions;
  LensOptions lensOptions;
  std::string size = "640x360";
  uint32_t frames = 10, comparisonRays = 4;
  bool json = false;
  ArgParser parser("bench", "[options]",
                   "Measures BVH build time, G-buffer time and reference ray traversal speed\n"
                   "(1 ray per pixel), whole postprocess, hybrid and raytrace frames side by\n"
                   "side, and lens-only (focus pull) frames on a still view whose G-buffer is\n"
                   "reused, and prints medians. Example:\n"
                   "  hdof bench --scene assets/scenes/living-room/living-room.gltf "
                   "--camera closeup");
  addSceneOptions(parser, sceneOptions);
  addLensOptions(parser, lensOptions);
  parser.option("--size", "WxH", "image size (default 640x360)", &size);
  parser.option("--frames", "N", "frames measured per figure, after one warm-up (default 10)",
                &frames);
  parser.option("--rays", "N",
                "rays per pixel per frame for the postprocess / hybrid / raytrace comparison "
                "(default 4)",
                &comparisonRays);
  parser.flag("--json", "print one JSON object instead of lines", &json);
  if (!parser.parse(args)) return 0;
  Size2 imageSize = parseSize(size, 4096);
  if (frames < 1 || frames > 10000) throw UsageError("--frames must be 1 to 10000");
  if (comparisonRays < 1 || comparisonRays > 64) throw UsageError("--rays must be 1 to 64");

  RenderSetup setup(sceneOptions, lensOptions, imageSize);
  const LoadedScene& loaded = setup.loaded;
  FrameRequest& request = setup.request;
  std::vector<double> buildMs;
  for (int i = 0; i < 3; ++i)
    buildMs.push_back(buildBvh(loaded.scene.vertices, loaded.scene.indices).buildMs);

  std::vector<double> wallMs;  // of the last measure(): submit to finish, the timestamps' check
  auto measure = [&](RenderMode mode, std::initializer_list<const char*> passes) {
    request.mode = mode;
    std::vector<double> ms;
    wallMs.clear();
    for (uint32_t i = 0; i <= frames; ++i) {
      request.settings.frameIndex = i;
      setup.pipeline.cut();  // every frame a view's first: the whole G-buffer runs
      FrameStats stats = setup.pipeline.render(request);
      double passMs = 0.0;
      for (const char* pass : passes) passMs += stats.passMsOf(pass);
      if (i == 0) continue;  // frame 0 warms up (shader compilation on some drivers)
      ms.push_back(passMs);
      wallMs.push_back(stats.wallMs);
    }
    return median(ms);
  };
  double visibilityMs = measure(RenderMode::Pinhole, {"visibility"});
  double resolveMs = measure(RenderMode::Pinhole, {"gbuffer"});
  double gbufferMs = measure(RenderMode::Pinhole, {"visibility", "gbuffer"});
  double postProcessMs = measure(RenderMode::PostProcess,
                                 {"dof_downsample", "dof_tiles", "dof_dilate",
                                  "dof_tile_lists_clear", "dof_tile_lists", "dof_prefilter",
                                  "dof_gather", "dof_median", "dof_composite_narrow",
                                  "dof_composite_wide", "dof_composite_near",
                                  "dof_composite_wider", "dof_composite_near_wider",
                                  "dof_composite_layers"});
  double postProcessFrameWallMs = median(wallMs);
  // Whole frames, side by side at the same rays per pixel: what the hybrid costs against the
  // post-process it improves on and the full ray trace it approaches (camera still, so the
  // hybrid's mask is the settled one).
  request.settings.samplesPerPixel = comparisonRays;
  // A frame's time is wall-clock, submit to finish, of untimed frames (as the daemon renders most
  // of its frames): on lavapipe the passes' timestamps cost a few percent of a frame and do not
  // add up to it (a pass's end stamp can precede its work, and the gaps between passes are
  // missing). The same frames rendered again with timestamps give the passes' times, whose sum is
  // printed beside it.
  std::vector<double> coverage, raysShot, gpuMs;
  PassTimes passMs;  // of the last timedFrames()
  auto renderFrames = [&](RenderMode mode, bool timed, auto&& onFrame) {
    request.mode = mode;
    request.timePasses = timed;
    setup.pipeline.resetHistory();
    for (uint32_t i = 0; i <= frames; ++i) {
      request.settings.frameIndex = i;
      FrameStats stats = setup.pipeline.render(request);
      if (i > 0) onFrame(stats);
    }
    request.timePasses = true;
  };
  auto timedFrames = [&](RenderMode mode) {
    gpuMs.clear();
    coverage.clear();
    raysShot.clear();
    passMs = {};
    renderFrames(mode, true, [&](const FrameStats& stats) {
      gpuMs.push_back(stats.gpuMs);
      coverage.push_back(stats.maskCoverage);
      raysShot.push_back(double(stats.raysShot));
      passMs.add(stats);
    });
  };
  auto frameMs = [&](RenderMode mode) {
    std::vector<double> ms;
    renderFrames(mode, false, [&](const FrameStats& stats) { ms.push_back(stats.wallMs); });
    timedFrames(mode);
    return median(ms);
  };
  double postProcessFrameMs = frameMs(RenderMode::PostProcess);
  double postProcessGpuMs = median(gpuMs);
  double hybridFrameMs = frameMs(RenderMode::Hybrid);
  double hybridGpuMs = median(gpuMs);
  double maskCoverage = median(coverage);
  double hybridRays = median(raysShot);
  PassTimes hybridPasses = passMs;
  // How the selective trace scales: the same pass with every pixel listed.
  double maskedTraceMs = passMs.medianOf("hybrid_trace");
  request.traceEverywhere = true;
  timedFrames(RenderMode::Hybrid);
  request.traceEverywhere = false;
  double fullTraceMs = passMs.medianOf("hybrid_trace");
  double fullRays = median(raysShot);
  double rayTraceFrameMs = frameMs(RenderMode::RayTrace);
  double rayTraceGpuMs = median(gpuMs);

  // Lens-only frames: a focus pull (the focus moving back and forth by 5%) on a still view whose
  // raster has all its samples, so that only the steps after the G-buffer run.
  auto settle = [&](RenderMode mode) {
    request.mode = mode;
    request.timePasses = false;
    setup.pipeline.resetHistory();
    for (uint32_t i = 0; i < gpu::kStillRasterFrames; ++i) setup.pipeline.render(request);
  };
  // A focus pull's frames: without timestamps for their wall-clock time, with them for the
  // passes' times.
  auto focusPull = [&](RenderMode mode, bool timed, auto&& onFrame) {
    settle(mode);
    request.timePasses = timed;
    float focus = request.lens.focusDistance;
    for (uint32_t i = 0; i < frames; ++i) {
      request.lens.focusDistance = focus * (i % 2 == 0 ? 1.05f : 1.0f);
      onFrame(setup.pipeline.render(request));
    }
    request.lens.focusDistance = focus;
    request.timePasses = true;
  };
  // The median wall-clock time of a run's untimed frames (focusPull, movingFrames).
  auto wallMedian = [&](auto&& run, RenderMode mode) {
    std::vector<double> ms;
    run(mode, false, [&](const FrameStats& stats) { ms.push_back(stats.wallMs); });
    return median(ms);
  };
  double postProcessFocusPullMs = wallMedian(focusPull, RenderMode::PostProcess);
  double hybridFocusPullMs = wallMedian(focusPull, RenderMode::Hybrid);
  PassTimes postProcessFocusPullPasses, focusPullPasses;
  focusPull(RenderMode::PostProcess, true,
            [&](const FrameStats& stats) { postProcessFocusPullPasses.add(stats); });
  std::vector<double> focusPullRays;
  focusPull(RenderMode::Hybrid, true, [&](const FrameStats& stats) {
    focusPullPasses.add(stats);
    focusPullRays.push_back(double(stats.raysShot));
  });

  // Frames of a turning camera (a quarter of a degree a frame, a slow drag's): every frame a new
  // view, whose G-buffer runs and whose history is reprojected, after three such frames so that
  // the history is one of motion.
  auto movingFrames = [&](RenderMode mode, bool timed, auto&& onFrame) {
    request.mode = mode;
    request.timePasses = timed;
    setup.pipeline.resetHistory();
    Camera start = request.camera;
    glm::vec3 right = glm::normalize(glm::cross(start.forward, start.up));
    for (uint32_t i = 0; i < frames + 3; ++i) {
      float angle = glm::radians(0.25f) * float(i);
      request.camera.forward =
          glm::normalize(std::cos(angle) * start.forward + std::sin(angle) * right);
      FrameStats stats = setup.pipeline.render(request);
      if (i >= 3) onFrame(stats);
    }
    request.camera = start;
    request.timePasses = true;
  };
  double postProcessMovingMs = wallMedian(movingFrames, RenderMode::PostProcess);
  double hybridMovingMs = wallMedian(movingFrames, RenderMode::Hybrid);
  PassTimes movingPasses;
  movingFrames(RenderMode::Hybrid, true, [&](const FrameStats& stats) { movingPasses.add(stats); });

  // The hybrid's frames once the view rests (nothing changed for kStillRasterFrames frames): the
  // G-buffer stands and every pixel gets rays, the frames an equal-time comparison spends most of
  // its time on.
  settle(RenderMode::Hybrid);
  std::vector<double> restMs, restRays;
  for (uint32_t i = 0; i < frames; ++i) {
    FrameStats stats = setup.pipeline.render(request);
    restMs.push_back(stats.wallMs);
    restRays.push_back(double(stats.raysShot));
  }
  // As many further frames at rest with timestamps.
  request.timePasses = true;
  PassTimes restPasses;
  for (uint32_t i = 0; i < frames; ++i) restPasses.add(setup.pipeline.render(request));
  double hybridRestMs = median(restMs);

  // Frame `index` after a cut. The first: no history, one raster sample whose edges the
  // anti-aliasing smooths spatially; what a new session's first frame and every camera jump cost.
  // The second: the first of a still view's multisampled frames (kMultisampledFrames).
  auto frameAfterCutMs = [&](RenderMode mode, uint32_t index) {
    request.mode = mode;
    request.timePasses = false;
    std::vector<double> ms;
    for (uint32_t i = 0; i < frames; ++i) {
      setup.pipeline.resetHistory();
      for (uint32_t before = 0; before < index; ++before) setup.pipeline.render(request);
      ms.push_back(setup.pipeline.render(request).wallMs);
    }
    request.timePasses = true;
    return median(ms);
  };
  double postProcessCutMs = frameAfterCutMs(RenderMode::PostProcess, 0);
  double hybridCutMs = frameAfterCutMs(RenderMode::Hybrid, 0);
  double postProcessMultisampledMs = frameAfterCutMs(RenderMode::PostProcess, 1);
  double hybridMultisampledMs = frameAfterCutMs(RenderMode::Hybrid, 1);

  request.settings.samplesPerPixel = 1;
  double referenceMs = measure(RenderMode::Reference, {"reference"});
  double rays = double(imageSize.width) * imageSize.height;
  double mraysPerSecond = rays / (referenceMs * 1e-3) * 1e-6;

  const Lens& lens = setup.request.lens;
  glm::vec2 fov = fieldOfViewDeg(lens, imageSize.width, imageSize.height);
  if (json) {
    std::printf(
        "{\"device\":\"%s\",\"scene\":\"%s\",\"triangles\":%zu,\"width\":%u,\"height\":%u,"
        "\"bvh_build_ms\":%.2f,\"bvh_nodes\":%zu,\"bvh_depth\":%u,\"gbuffer_ms\":%.3f,"
        "\"visibility_ms\":%.3f,\"resolve_ms\":%.3f,\"postprocess_dof_ms\":%.3f,"
        "\"reference_ms\":%.3f,\"reference_mrays_per_s\":%.3f,\"frames\":%u,"
        "\"comparison_rays_per_pixel\":%u,\"postprocess_frame_ms\":%.3f,"
        "\"hybrid_frame_ms\":%.3f,\"raytrace_frame_ms\":%.3f,\"postprocess_frame_gpu_ms\":%.3f,"
        "\"hybrid_frame_gpu_ms\":%.3f,\"raytrace_frame_gpu_ms\":%.3f,\"mask_coverage\":%.4f,"
        "\"hybrid_rays_per_frame\":%.0f,\"hybrid_passes_ms\":{%s},"
        "\"full_mask_trace_ms\":%.3f,\"full_mask_rays_per_frame\":%.0f,"
        "\"postprocess_focus_pull_ms\":%.3f,\"postprocess_focus_pull_passes_ms\":{%s},"
        "\"hybrid_focus_pull_ms\":%.3f,"
        "\"hybrid_focus_pull_rays_per_frame\":%.0f,\"hybrid_focus_pull_passes_ms\":{%s},"
        "\"postprocess_cut_frame_ms\":%.3f,\"hybrid_cut_frame_ms\":%.3f,"
        "\"postprocess_multisampled_frame_ms\":%.3f,\"hybrid_multisampled_frame_ms\":%.3f,"
        "\"hybrid_rest_frame_ms\":%.3f,\"hybrid_rest_rays_per_frame\":%.0f,"
        "\"hybrid_rest_passes_ms\":{%s},"
        "\"postprocess_moving_frame_ms\":%.3f,\"hybrid_moving_frame_ms\":%.3f,"
        "\"hybrid_moving_passes_ms\":{%s},"
        "\"lens\":{\"focal_length_mm\":%.3f,\"f_number\":%.4g,\"focus_distance\":%.4f,"
        "\"sensor_width_mm\":%.4g,\"sensor_height_mm\":%.4g,\"fov_x_deg\":%.3f,"
        "\"fov_y_deg\":%.3f}}\n",
        setup.context.deviceName().c_str(), loaded.scene.name.c_str(), loaded.scene.triangleCount(),
        imageSize.width, imageSize.height, median(buildMs), loaded.bvh.nodes.size(),
        loaded.bvh.depth, gbufferMs, visibilityMs, resolveMs, postProcessMs, referenceMs,
        mraysPerSecond, frames, comparisonRays, postProcessFrameMs, hybridFrameMs, rayTraceFrameMs,
        postProcessGpuMs, hybridGpuMs, rayTraceGpuMs, maskCoverage, hybridRays,
        hybridPasses.text(true).c_str(), fullTraceMs, fullRays, postProcessFocusPullMs,
        postProcessFocusPullPasses.text(true).c_str(), hybridFocusPullMs, median(focusPullRays),
        focusPullPasses.text(true).c_str(), postProcessCutMs, hybridCutMs,
        postProcessMultisampledMs, hybridMultisampledMs, hybridRestMs, median(restRays),
        restPasses.text(true).c_str(), postProcessMovingMs, hybridMovingMs,
        movingPasses.text(true).c_str(), lens.focalLengthMm, lens.fNumber, lens.focusDistance,
        lens.sensor.widthMm, lens.sensor.heightMm, fov.x, fov.y);
    return 0;
  }
  std::printf("device=\"%s\"\n", setup.context.deviceName().c_str());
  std::printf("scene=%s triangles=%zu size=%ux%u\n", loaded.scene.name.c_str(),
              loaded.scene.triangleCount(), imageSize.width, imageSize.height);
  std::printf("lens: %s\n", lensSummary(lens, imageSize).c_str());
  std::printf("bvh_build_ms=%.1f bvh_nodes=%zu bvh_depth=%u (median of 3)\n", median(buildMs),
              loaded.bvh.nodes.size(), loaded.bvh.depth);
  std::printf("gbuffer_ms=%.2f visibility_ms=%.2f resolve_ms=%.2f (medians of %u frames)\n",
              gbufferMs, visibilityMs, resolveMs, frames);
  std::printf("postprocess_dof_ms=%.2f postprocess_frame_wall_ms=%.2f (medians)\n", postProcessMs,
              postProcessFrameWallMs);
  std::printf("reference_ms=%s reference_mrays_per_s=%.2f (1 ray per pixel, median of %u frames)\n",
              msText(referenceMs).c_str(), mraysPerSecond, frames);
  std::printf(
      "frame_ms at %u rays per pixel: postprocess=%s hybrid=%s raytrace=%s "
      "(hybrid/postprocess %.2fx, hybrid/raytrace %.2fx, mask coverage %.3f; wall clock, "
      "medians of %u)\n",
      comparisonRays, msText(postProcessFrameMs).c_str(), msText(hybridFrameMs).c_str(),
      msText(rayTraceFrameMs).c_str(), hybridFrameMs / postProcessFrameMs,
      hybridFrameMs / rayTraceFrameMs, maskCoverage, frames);
  std::printf(
      "frame_gpu_ms: postprocess=%s hybrid=%s raytrace=%s (the passes' timestamps added up)\n",
      msText(postProcessGpuMs).c_str(), msText(hybridGpuMs).c_str(), msText(rayTraceGpuMs).c_str());
  std::printf(
      "focus_pull_frame_ms: postprocess=%s hybrid=%s (lens-only frames on a settled still "
      "view; wall clock, medians of %u)\n",
      msText(postProcessFocusPullMs).c_str(), msText(hybridFocusPullMs).c_str(), frames);
  std::printf(
      "cut_frame_ms: postprocess=%s hybrid=%s (the first frame of a view, without history; "
      "wall clock, medians of %u)\n",
      msText(postProcessCutMs).c_str(), msText(hybridCutMs).c_str(), frames);
  std::printf(
      "multisampled_frame_ms: postprocess=%s hybrid=%s (a still view's second frame, %u "
      "raster samples per pixel; wall clock, medians of %u)\n",
      msText(postProcessMultisampledMs).c_str(), msText(hybridMultisampledMs).c_str(),
      gpu::kStillRasterSamples, frames);
  std::printf(
      "rest_frame_ms: hybrid=%s (hybrid/raytrace %.2fx, %.0f rays; a view at rest after %u "
      "frames, the G-buffer kept; wall clock, medians of %u)\n",
      msText(hybridRestMs).c_str(), hybridRestMs / rayTraceFrameMs, median(restRays),
      gpu::kStillRasterFrames, frames);
  std::printf("hybrid_rest_passes_ms:%s (medians)\n", restPasses.text(false).c_str());
  std::printf(
      "moving_frame_ms: postprocess=%s hybrid=%s (a camera turning 0.25 degrees a frame; wall "
      "clock, medians of %u)\n",
      msText(postProcessMovingMs).c_str(), msText(hybridMovingMs).c_str(), frames);
  std::printf("hybrid_moving_passes_ms:%s (medians)\n", movingPasses.text(false).c_str());
  std::printf("hybrid_rays_per_frame=%.0f (%.2f per pixel of the image, %.2f per traced pixel)\n",
              hybridRays, hybridRays / (double(imageSize.width) * imageSize.height),
              hybridRays / std::max(maskCoverage * imageSize.width * imageSize.height, 1.0));
  std::printf("hybrid_passes_ms:%s (medians)\n", hybridPasses.text(false).c_str());
  std::printf("postprocess_focus_pull_passes_ms:%s (medians)\n",
              postProcessFocusPullPasses.text(false).c_str());
  std::printf("hybrid_focus_pull_passes_ms:%s (%.0f rays; medians)\n",
              focusPullPasses.text(false).c_str(), median(focusPullRays));
  std::printf(
      "hybrid_trace: %s ms for the mask's rays (%.2f Mrays/s), %s ms with every pixel "
      "traced (%.0f rays, %.2f Mrays/s): the mask's share of the work %.2f\n",
      msText(maskedTraceMs).c_str(), hybridRays / (maskedTraceMs * 1e3),
      msText(fullTraceMs).c_str(), fullRays, fullRays / (fullTraceMs * 1e3),
      maskedTraceMs / fullTraceMs);
  return 0;
}

}  // namespace hdof
