// The hybrid depth of field (Tan, Chua, Biette, Bhojan 2020), passes 3-7 after the G-buffer and
// the post-process: the adaptive ray mask, the selective ray trace over its work list, temporal
// accumulation, spatial reconstruction and the composite. Owns its images and the temporal history.
#pragma once

#include "render/debug_view_pass.h"
#include "render/hybrid_composite_pass.h"
#include "render/hybrid_spatial_pass.h"
#include "render/hybrid_temporal_pass.h"
#include "render/hybrid_trace_pass.h"
#include "render/ray_mask.h"

#include <memory>

namespace hdof {

class HybridDof {
 public:
  HybridDof(const gpu::Context& context, const GpuScene& scene, uint32_t width, uint32_t height);
  ~HybridDof();

  void resize(uint32_t width, uint32_t height);
  // Forgets the history: the next frame starts the accumulation over (a cut).
  void resetHistory() { hasHistory_ = false; }
  // Reads the G-buffer in targets and the post-process's output. raysPerPixel (the frame
  // uniforms' samples per pixel) caps the mask's rays.
  // view other than Final draws that debug view into output() instead of the composite.
  // traceEverywhere: a full mask (every pixel gets the full rays).
  void record(VkCommandBuffer cmd, gpu::GpuTimer& timer, const gpu::Buffer& frameUniforms,
              const RenderTargets& targets, const gpu::Image& postProcess,
              DebugView view = DebugView::Final, bool traceEverywhere = false);

  // rgba16f, full resolution, HDR.
  const gpu::Image& output() const { return *output_; }
  // After the frame has finished: the fraction of pixels the mask traced.
  double maskCoverage() const { return mask_.coverage(); }
  uint64_t raysShot() const { return mask_.raysShot(); }

 private:
  const gpu::Context& context_;
  RayMask mask_;
  std::unique_ptr<HybridTraceLayers> layers_;
  HybridTracePass trace_;
  HybridTemporalPass temporal_;
  HybridSpatialPass spatial_;
  HybridCompositePass composite_;
  DebugViewPass debugView_;
  std::unique_ptr<gpu::Image> output_;
  bool hasHistory_ = false;
};

}  // namespace hdof
