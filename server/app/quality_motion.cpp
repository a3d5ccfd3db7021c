#include "app/quality_motion.h"

#include "app/progress.h"
#include "encode/image_file.h"
#include "quality/occlusion_mask.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>

namespace hdof {
namespace {

struct Checkpoint {
  uint32_t frame;  // 0-based frame on the path
  ImageRgba8 reference, region;
  bool hasRegion;
};

struct MotionRow {
  RenderMode mode;
  double psnrDb = 0.0, ssim = 0.0, psnrOcclDb = 0.0, ssimOccl = 0.0, msPerFrame = 0.0;
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
      std::vector<uint8_t> region =
          occlusionMask(pipeline.linearDepth(), width, height,
                        cocParameters(request.camera, request.lens, width, height));
      uint64_t done = uint64_t(i - 1) * options.referenceRays;
      pipeline.renderReference(request, options.referenceRays,
                               [&](uint32_t rays) { progress.update(done + rays); });
      checkpoints.push_back(
          {frame, pipeline.image(), maskImage(region, width, height), maskCount(region) > 0});
      writeImage(outPath("motion-reference-" + std::to_string(frame) + ".png"),
                 checkpoints.back().reference);
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
    size_t next = 0, regions = 0;
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
      ImageComparison whole = compareImages(image, checkpoint.reference);
      row.psnrDb += whole.psnrDb / double(checkpoints.size());
      row.ssim += whole.ssim / double(checkpoints.size());
      if (!checkpoint.hasRegion) continue;
      ImageComparison occluded = compareImages(image, checkpoint.reference, &checkpoint.region);
      row.psnrOcclDb += occluded.psnrDb;
      row.ssimOccl += occluded.ssim;
      ++regions;
    }
    if (regions) {
      row.psnrOcclDb /= double(regions);
      row.ssimOccl /= double(regions);
    }
    row.msPerFrame = median(frameMs);
    rows.push_back(row);
  }

  if (options.json) {
    nlohmann::json out;
    out["motion"] = {{"frames", options.frames},
                     {"compared_frames", options.evaluations},
                     {"reference_rays_per_pixel", options.referenceRays}};
    for (const MotionRow& r : rows)
      out["modes"].push_back({{"mode", modeName(r.mode)},
                              {"psnr_db", r.psnrDb},
                              {"ssim", r.ssim},
                              {"psnr_occl_db", r.psnrOcclDb},
                              {"ssim_occl", r.ssimOccl},
                              {"ms_per_frame", r.msPerFrame}});
    std::printf("%s\n", out.dump(2).c_str());
    return;
  }
  std::printf(
      "in motion: %u frames along the path, compared at %u of them with %u-ray references\n",
      options.frames, options.evaluations, options.referenceRays);
  for (const MotionRow& r : rows)
    std::printf(
        "mode=%s psnr_db=%.2f ssim=%.4f psnr_occl_db=%.2f ssim_occl=%.4f "
        "ms_per_frame=%.1f (means over the compared frames)\n",
        modeName(r.mode), r.psnrDb, r.ssim, r.psnrOcclDb, r.ssimOccl, r.msPerFrame);
}

}  // namespace hdof
