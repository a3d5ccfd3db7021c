#include "app/quality_motion.h"

#include "app/progress.h"
#include "encode/image_file.h"
#include "quality/gbuffer_geometry.h"
#include "quality/quality_regions.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>

namespace hdof {
namespace {

struct Checkpoint {
  uint32_t frame;  // 0-based frame on the path
  ImageRgba8 reference;
  QualityRegions regions;
};

// A mean over the compared frames whose region is not empty.
struct Mean {
  double psnrDb = 0.0, ssim = 0.0;
  uint32_t count = 0;
  void add(const ImageComparison& c) {
    psnrDb += c.psnrDb;
    ssim += c.ssim;
    ++count;
  }
  double meanPsnrDb() const { return count ? psnrDb / count : 0.0; }
  double meanSsim() const { return count ? ssim / count : 0.0; }
};

struct MotionRow {
  RenderMode mode;
  Mean whole, occluded, edge;
  double msPerFrame = 0.0;
};

}  // namespace

void measureQualityInMotion(RenderSetup& setup, const CameraPath& path,
                            const MotionQualityOptions& options) {
  FramePipeline& pipeline = setup.pipeline;
  FrameRequest request = setup.request;
  const Camera baseCamera = request.camera;
  const Lens baseLens = request.lens;
  const uint32_t width = request.settings.width, height = request.settings.height;
  auto moveTo = [&](uint32_t frame) {
    path.sample(float(frame) / float(options.frames - 1), baseCamera, baseLens, request.camera,
                request.lens);
    request.settings.frameIndex = frame;
  };
  auto outPath = [&](const std::string& name) {
    return (std::filesystem::path(options.outDir) / name).string();
  };

  std::vector<Checkpoint> checkpoints;
  {
    Progress progress("references", uint64_t(options.evaluations) * options.referenceRays);
    for (uint32_t i = 1; i <= options.evaluations; ++i) {
      uint32_t frame = (options.frames * i) / options.evaluations - 1;
      moveTo(frame);
      request.mode = RenderMode::Pinhole;
      pipeline.cut();
      pipeline.render(request);
      QualityRegions regions =
          qualityRegions(readGBufferGeometry(setup.context, pipeline), width, height,
                         cocParameters(request.lens, width, height));
      uint64_t done = uint64_t(i - 1) * options.referenceRays;
      pipeline.renderReference(request, options.referenceRays,
                               [&](uint32_t rays) { progress.update(done + rays); });
      checkpoints.push_back({frame, pipeline.image(), std::move(regions)});
      const Checkpoint& checkpoint = checkpoints.back();
      auto file = [&](const char* name) {
        return outPath(std::string(name) + "-" + std::to_string(frame) + ".png");
      };
      writeImage(file("motion-reference"), checkpoint.reference);
      writeImage(file("motion-occlusion-mask"), checkpoint.regions.occlusion);
      writeImage(file("motion-edge-mask"), checkpoint.regions.edge);
    }
  }

  std::vector<MotionRow> rows;
  for (RenderMode mode : options.modes) {
    MotionRow row{mode};
    request.mode = mode;
    request.settings.samplesPerPixel =
        mode == RenderMode::Hybrid || mode == RenderMode::RayTrace ? options.raysPerPixel : 1;
    pipeline.resetHistory();
    pipeline.cut();
    std::vector<double> frameMs;
    size_t next = 0;
    for (uint32_t frame = 0; frame < options.frames && next < checkpoints.size(); ++frame) {
      moveTo(frame);
      frameMs.push_back(pipeline.render(request).gpuMs);
      const Checkpoint& checkpoint = checkpoints[next];
      if (frame != checkpoint.frame) continue;
      ++next;
      ImageRgba8 image = pipeline.image();
      writeImage(
          outPath(std::string("motion-") + modeName(mode) + "-" + std::to_string(frame) + ".png"),
          image);
      QualityScores scores = scoreImage(image, checkpoint.reference, checkpoint.regions);
      row.whole.add(scores.whole);
      if (scores.occlusion) row.occluded.add(*scores.occlusion);
      if (scores.edge) row.edge.add(*scores.edge);
    }
    row.msPerFrame = median(frameMs);
    rows.push_back(row);
  }

  if (options.json) {
    nlohmann::json out;
    out["motion"] = {{"frames", options.frames},
                     {"compared_frames", options.evaluations},
                     {"reference_rays_per_pixel", options.referenceRays}};
    // A region empty at every compared frame has no figures (null).
    auto db = [](const Mean& m) {
      return m.count ? nlohmann::json(m.meanPsnrDb()) : nlohmann::json(nullptr);
    };
    auto ssim = [](const Mean& m) {
      return m.count ? nlohmann::json(m.meanSsim()) : nlohmann::json(nullptr);
    };
    for (const MotionRow& r : rows)
      out["modes"].push_back({{"mode", modeName(r.mode)},
                              {"psnr_db", r.whole.meanPsnrDb()},
                              {"ssim", r.whole.meanSsim()},
                              {"psnr_occl_db", db(r.occluded)},
                              {"ssim_occl", ssim(r.occluded)},
                              {"psnr_edge_db", db(r.edge)},
                              {"ssim_edge", ssim(r.edge)},
                              {"ms_per_frame", r.msPerFrame}});
    std::printf("%s\n", out.dump(2).c_str());
    return;
  }
  std::printf(
      "in motion: %u frames along the path, compared at %u of them with %u-ray references\n",
      options.frames, options.evaluations, options.referenceRays);
  auto db = [](const Mean& m) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.2f", m.meanPsnrDb());
    return m.count ? std::string(text) : std::string("none");
  };
  auto ssim = [](const Mean& m) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.4f", m.meanSsim());
    return m.count ? std::string(text) : std::string("none");
  };
  for (const MotionRow& r : rows)
    std::printf(
        "mode=%s psnr_db=%.2f ssim=%.4f psnr_occl_db=%s ssim_occl=%s psnr_edge_db=%s "
        "ssim_edge=%s ms_per_frame=%.1f (means over the compared frames)\n",
        modeName(r.mode), r.whole.meanPsnrDb(), r.whole.meanSsim(), db(r.occluded).c_str(),
        ssim(r.occluded).c_str(), db(r.edge).c_str(), ssim(r.edge).c_str(), r.msPerFrame);
}

}  // namespace hdof
