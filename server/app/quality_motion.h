// hdof quality --camera-path: the modes in motion. The camera follows a path over N frames and
// each mode renders every frame (its temporal history following the motion); at evenly spaced
// frames the image is compared with a thin-lens reference of that frame's view.
#pragma once

#include "app/render_setup.h"
#include "render/camera_path.h"

#include <string>
#include <vector>

namespace hdof {

struct MotionQualityOptions {
  uint32_t frames = 32;          // frames along the path
  uint32_t evaluations = 4;      // frames compared (the last, and evenly before it)
  uint32_t referenceRays = 256;  // rays per pixel of each reference
  uint32_t raysPerPixel = 4;     // hybrid and raytrace, per frame
  std::vector<RenderMode> modes;
  std::string outDir;
  bool json = false;
};

// Prints one line per mode (or JSON): mean PSNR and SSIM over the compared frames, whole image,
// partial-occlusion region and in-focus edge band (each region's mean over the frames where it is
// not empty), and the median GPU time per frame. Writes each compared frame's reference, region
// masks and images to options.outDir.
void measureQualityInMotion(RenderSetup& setup, const CameraPath& path,
                            const MotionQualityOptions& options);

}  // namespace hdof
