#include "quality/reference_image.h"

#include <algorithm>
#include <cstdio>

namespace hdof {

std::string ReferenceImage::verdict() const {
  char text[256];
  if (lastStepDb == 0.0)
    std::snprintf(text, sizeof(text), "%u rays per pixel, as asked (no convergence test)", rays);
  else {
    char region[64] = "";
    if (measuredRegion)
      std::snprintf(region, sizeof(region), " (%.1f dB in the occlusion region)", lastStepRegionDb);
    std::snprintf(text, sizeof(text),
                  "%u rays per pixel; the image at %u rays differs from it by PSNR %.1f dB%s, %s",
                  rays, rays / 2, lastStepDb, region,
                  converged ? "so it is converged to about that level"
                            : "short of the target: raise --max-reference-spp");
  }
  return text;
}

ReferenceImage renderConvergedReference(FramePipeline& pipeline, FrameRequest request,
                                        const ReferenceOptions& options,
                                        const std::function<void(uint32_t)>& onProgress) {
  ReferenceImage result;
  request.firstSample = 0;
  request.accumulate = false;
  if (options.fixedRays > 0) {
    result.gpuMs = pipeline.renderReference(request, options.fixedRays, onProgress).gpuMs;
    result.image = pipeline.image();
    result.rays = options.fixedRays;
    result.converged = true;
    return result;
  }
  uint32_t rays = options.startRays;
  result.gpuMs += pipeline.renderReference(request, rays, onProgress).gpuMs;
  ImageRgba8 previous = pipeline.image();
  while (rays < options.maxRays) {
    request.firstSample = rays;
    request.accumulate = true;
    result.gpuMs += pipeline
                        .renderReference(request, rays,
                                         [&](uint32_t done) {
                                           if (onProgress) onProgress(rays + done);
                                         })
                        .gpuMs;
    rays *= 2;
    ImageRgba8 current = pipeline.image();
    result.lastStepDb = compareImages(previous, current).psnrDb;
    result.measuredRegion = options.region != nullptr;
    result.lastStepRegionDb =
        options.region ? compareImages(previous, current, options.region).psnrDb : 0.0;
    previous = std::move(current);
    if (rays >= std::min(options.minRays, options.maxRays) &&
        result.lastStepDb >= options.targetDb &&
        (!options.region || result.lastStepRegionDb >= options.targetDb)) {
      result.converged = true;
      break;
    }
  }
  result.image = std::move(previous);
  result.rays = rays;
  return result;
}

}  // namespace hdof
