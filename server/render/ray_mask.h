// Pass 3 of the frame pipeline, the adaptive ray mask: where the selective ray tracer traces and
// how many rays per pixel. Edges of the filtered G-buffer (Sobel, like Canny) whose near side is
// out of focus, dilated per pixel by that side's CoC disc (where partial occlusion shows), plus
// where the ray-traced output's luminance variance is high. Ends with a compacted work list of
// those pixels and its indirect dispatch arguments. Owns its images and buffers.
#pragma once

#include "gpu/timestamps.h"
#include "render/dof_dilate.h"
#include "render/dof_tiles.h"
#include "render/ray_mask_compact.h"
#include "render/ray_mask_edges.h"
#include "render/ray_mask_rays.h"
#include "render/ray_mask_spread.h"
#include "render/render_targets.h"

#include <memory>

namespace hdof {

class RayMask {
 public:
  RayMask(const gpu::Context& context, uint32_t width, uint32_t height);
  ~RayMask();
  RayMask(const RayMask&) = delete;
  RayMask& operator=(const RayMask&) = delete;

  // Remakes the images and buffers for a new viewport (waits for the queue first).
  void resize(uint32_t width, uint32_t height);
  // Reads targets.normalDepth and, when not null, a per-pixel luminance variance (any
  // single-channel float format, sampled usage; null reads as zero). Each pass is timed as
  // "ray_mask_<pass>". Ends with rays() and workList() visible to compute shaders and to
  // vkCmdDispatchIndirect, and the list's header on its way to the CPU.
  // everywhere: every pixel gets the full rays.
  void record(VkCommandBuffer cmd, gpu::GpuTimer& timer, const gpu::Buffer& frameUniforms,
              const RenderTargets& targets, const gpu::Image* varianceOrNull,
              bool everywhere = false) const;

  // r8ui, full resolution: rays per pixel, 0 where the post-process is good enough.
  const gpu::Image& rays() const;
  // shared/ray_work.h: a RayWorkHeader (dispatch arguments at offset 0), then the entries.
  const gpu::Buffer& workList() const;
  // After the recorded command buffer has finished: the pixels listed, and their fraction.
  uint32_t listedPixels() const;
  double coverage() const;
  uint64_t raysShot() const;

 private:
  struct Resources;
  const gpu::Context& context_;
  std::unique_ptr<Resources> resources_;
  RayMaskEdgesPass edges_;
  // The post-process's tile max and tile dilation, run on the edges' reach: per tile, the
  // largest disc that can cover a pixel of it, which bounds the dilation's search there.
  DofTilesPass tiles_;
  DofDilatePass dilate_;
  RayMaskSpreadPass spread_;
  RayMaskRaysPass rays_;
  RayMaskCompactPass compact_;
};

}  // namespace hdof
