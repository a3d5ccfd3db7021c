// A converged thin-lens reference: rays per pixel double until the image stops changing.
#pragma once

#include "render/frame_pipeline.h"

#include <functional>
#include <string>

namespace hdof {

struct ReferenceOptions {
  uint32_t fixedRays = 0;  // > 0: exactly this many rays per pixel, no convergence test
  uint32_t startRays = 16;
  // Not converged before this many (unless maxRays is fewer): the reference's error adds to
  // every mode's, and in the 3 s of an equal-time run the ray tracer gets up to about 170 rays.
  uint32_t minRays = 256;
  uint32_t maxRays = 1024;
  double targetDb = 42.0;  // PSNR between the image at N and at N/2 rays that counts as converged
  // Where given, the PSNR inside this mask (white pixels) must reach the target too: the blurred
  // silhouettes that quality is measured on are the noisiest part of the image.
  const ImageRgba8* region = nullptr;
};

struct ReferenceImage {
  ImageRgba8 image;
  uint32_t rays = 0;
  double lastStepDb = 0.0;        // PSNR between the images at rays and rays/2 (0 when fixed)
  double lastStepRegionDb = 0.0;  // the same inside options.region
  bool measuredRegion = false;    // whether there was a region (else lastStepRegionDb is 0)
  bool converged = false;
  double gpuMs = 0.0;
  // One sentence on how convergence was decided, for the user.
  std::string verdict() const;
};

// Doubling N, the difference between the N and N/2 images is half the N/2 image's noise, so its
// PSNR estimates how far the N-ray image is from the limit. Reuses the N/2 rays (the sample
// sequence continues), so the total cost is that of the final N.
ReferenceImage renderConvergedReference(FramePipeline& pipeline, FrameRequest request,
                                        const ReferenceOptions& options,
                                        const std::function<void(uint32_t)>& onProgress = {});

}  // namespace hdof
