// Pass 2 of the frame pipeline, the post-process depth of field (Jimenez 2014, "Next Generation
// Post Processing in Call of Duty: Advanced Warfare"), from the G-buffer's sharp colour and depth:
// CoC and half-resolution downsample, CoC tiles, tile dilation, prefilter, scatter-as-gather into
// a near and a far layer, median, full-resolution composite. Owns its intermediate images.
#pragma once

#include "gpu/timestamps.h"
#include "render/dof_composite.h"
#include "render/dof_dilate.h"
#include "render/dof_downsample.h"
#include "render/dof_gather.h"
#include "render/dof_median.h"
#include "render/dof_prefilter.h"
#include "render/dof_tiles.h"
#include "render/render_targets.h"

#include <memory>

namespace hdof {

class PostProcessDof {
 public:
  PostProcessDof(const gpu::Context& context, uint32_t width, uint32_t height);
  ~PostProcessDof();
  PostProcessDof(const PostProcessDof&) = delete;
  PostProcessDof& operator=(const PostProcessDof&) = delete;

  // Remakes the images for a new viewport (waits for the queue first).
  void resize(uint32_t width, uint32_t height);
  // Reads targets.color and targets.normalDepth; each pass is timed as "dof_<pass>". Ends with
  // the output written and visible to compute shaders.
  void record(VkCommandBuffer cmd, gpu::GpuTimer& timer, const gpu::Buffer& frameUniforms,
              const RenderTargets& targets) const;

  // rgba16f, full resolution, HDR with alpha 1.
  const gpu::Image& output() const;
  // r16f, full resolution: the signed CoC in pixels (negative: near field).
  const gpu::Image& coc() const;
  // rgba16f, half resolution, for debug views: the far layer (alpha: CoC) and the near layer
  // (premultiplied, alpha: opacity).
  const gpu::Image& farLayer() const;
  const gpu::Image& nearLayer() const;

 private:
  struct Images;
  const gpu::Context& context_;
  std::unique_ptr<Images> images_;
  DofDownsamplePass downsample_;
  DofTilesPass tiles_;
  DofDilatePass dilate_;
  DofPrefilterPass prefilter_;
  DofGatherPass gather_;
  DofMedianPass median_;
  DofCompositePass composite_;
};

}  // namespace hdof
