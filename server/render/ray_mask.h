// The adaptive ray mask: where the selective ray tracer traces and how many rays per pixel.
// Edges of the filtered G-buffer (Sobel, like Canny) whose near side is out of focus, dilated per
// pixel by that side's CoC disc (where partial occlusion shows), plus where the ray-traced
// output's luminance variance is high. Steps (shaders/ray_mask_*.comp, and the post-process's
// tile max and dilation run on the edges' reach): clear (the list's header), edges, tiles,
// dilate, far rows and columns (discs wider than the dilation reaches, per tile), spread along
// rows and along columns, rays (which also lists the pixels), indirect, readback (the header, for
// the frame's stats). Ends with a compacted work list of those pixels and its indirect dispatch
// arguments.
#pragma once

#include "render/frame_images.h"
#include "render/steps.h"

#include <shared/ray_work.h>

namespace hdof {

struct RayMaskOptions {
  // The edges, their tiles and spread that mask holds are those of this G-buffer and lens:
  // only the steps from the rays on run.
  bool edgesStand = false;
  bool everywhere = false;  // every pixel gets the full rays
  // A resting pixel of one ray a frame takes its rays in turns (ray_mask_rays.comp): only for a
  // frame whose consumers keep the last frame's values where a pixel is not listed.
  bool inTurns = false;
};

class RayMask {
 public:
  explicit RayMask(const gpu::Context& context);

  // Reads gbuffer.normalDepth and, when not null, a per-pixel luminance variance (any
  // single-channel float format; null reads as zero); writes mask. Ends with mask.rays and
  // mask.workList ready for compute shaders and vkCmdDispatchIndirect, and the list's header on
  // its way to mask.workHeader.
  void record(StepRecorder& steps, const GBufferImages& gbuffer, const RayMaskImages& mask,
              const gpu::Image* varianceOrNull, RayMaskOptions options = {}) const;

 private:
  gpu::ComputeProgram edges_;
  // The post-process's tile max and tile dilation, run on the edges' reach: per tile, the
  // largest disc that can cover a pixel of it, which bounds the dilation's search there.
  gpu::ComputeProgram tiles_, dilate_;
  gpu::ComputeProgram farRows_, farColumns_;
  gpu::ComputeProgram spread_, columns_, rays_, indirect_;
  gpu::ImageBatch noVarianceBatch_;
  gpu::Image noVariance_;  // r16f, 1x1, zero
};

// After the recorded frame has finished: the work list's header (pixels listed, rays).
gpu::RayWorkHeader readWorkHeader(const RayMaskImages& mask);

}  // namespace hdof
