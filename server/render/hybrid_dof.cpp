#include "render/hybrid_dof.h"

#include <algorithm>

namespace hdof {

using gpu::Grid;

HybridDof::HybridDof(const gpu::Context& context, const GpuScene& scene)
    : mask_(context),
      trace_(context, "hybrid_trace.comp", &scene.setLayout()),
      historyClear_(context, "hybrid_history_clear.comp"),
      temporalMoved_(context, "hybrid_temporal.comp"),
      temporalLens_(context, "hybrid_temporal.comp", nullptr, {{"kMovedFrames", 0}}),
      temporalStill_(context, "hybrid_temporal.comp", nullptr,
                     {{"kChangedFrames", 0}, {"kMovedFrames", 0}}),
      spatial_(context, "hybrid_spatial.comp"),
      composite_(context, "hybrid_composite.comp"),
      compositeMoving_(context, "hybrid_composite.comp", nullptr, {{"kCameraMoved", 1}}),
      debugView_(context, "debug_view.comp"),
      focusZone_(context, "focus_zone.comp") {}

void HybridDof::startFrame(const gpu::FrameUniforms& uniforms, bool maskEdgesStand, DebugView view,
                           bool traceEverywhere) {
  stillFrames_ = uniforms.stillFrames;
  // As hybrid_temporal.comp decides it: the camera moved, or the camera or the lens changed.
  moved_ = uniforms.previousViewProj != uniforms.viewProj;
  changed_ = moved_ || uniforms.stillFrames == 0;
  maskEdgesStand_ = maskEdgesStand;
  view_ = view;
  traceEverywhere_ = traceEverywhere;
  inTurns_ = hasHistory_ && lastDrewFinal_ && view == DebugView::Final &&
             stillFrames_ >= gpu::kStillRasterFrames;
}

void HybridDof::record(StepRecorder& steps, const FrameImages& images) const {
  const GBufferImages& g = images.gbuffer;
  const RayMaskImages& m = images.mask;
  const HybridImages& h = images.hybrid;
  const HybridImages::History& previous = h.history[current_];
  // A frame in which neither the camera nor the lens changed accumulates in place: the history
  // it reads is the pixel's own (hybrid_temporal.comp), and pixels not listed keep theirs.
  const HybridImages::History& next = changed_ ? h.history[current_ ^ 1u] : previous;

  mask_.record(
      steps, g, m, hasHistory_ ? &h.variance : nullptr,
      {.edgesStand = maskEdgesStand_, .everywhere = traceEverywhere_, .inTurns = inTurns_});
  // The work list starts with a VkDispatchIndirectCommand sized to its entries.
  steps.dispatch(trace_,
                 {{"workList", m.workList},
                  {"nearLayer", h.nearLayer},
                  {"farLayer", h.farLayer},
                  {"farPosition", h.farPosition},
                  {"layerCoc", h.layerCoc},
                  {"samplesTraced", h.samplesTraced}},
                 Grid::indirect(m.workList));
  // Pixels the mask left out this frame drop their history: the pass writes listed pixels only,
  // and a pixel's layers are read only where its moments count rays, so zeroing the moments and
  // the variance drops it (the layers' stale values stay unread). Once camera and lens have
  // rested kStillRasterFrames frames (ray_mask_rays.comp), or when every pixel is traced, every
  // pixel has rays: those taking turns keep their history between them.
  if (stillFrames_ < gpu::kStillRasterFrames && !traceEverywhere_) {
    steps.dispatch(historyClear_,
                   {{"rays", m.rays},
                    {"moments", next.moments},
                    {"variance", h.variance},
                    {"difference", h.difference}},
                   Grid::over(m.rays));
  }
  // The moving average's window (frames at the full rays per pixel): short after a change of view
  // or lens, so that the history follows it; on a still view it grows a frame per frame, so that
  // the average takes in every ray since the change (the noise keeps falling), up to 1024 frames
  // (a one-ray frame's share of 4096 rays is still far above a float history's rounding step).
  constexpr uint32_t kChangeWindow = 10, kStillWindow = 1024;
  struct {
    uint32_t reset;  // a cut or the first frame: no history at all
    float minBlend;  // the moving average's weight of the new frame once history is long
  } temporalPush{hasHistory_ ? 0u : 1u,
                 1.0f / float(std::min(kChangeWindow + stillFrames_, kStillWindow))};
  steps.dispatch(moved_     ? temporalMoved_
                 : changed_ ? temporalLens_
                            : temporalStill_,
                 {{"rays", m.rays},
                  {"nearLayer", h.nearLayer},
                  {"farLayer", h.farLayer},
                  {"farPosition", h.farPosition},
                  {"motion", g.motion},
                  {"normalDepth", g.normalDepth},
                  {"historyNear", previous.nearLayer},
                  {"historyFar", previous.farLayer},
                  {"historyMoments", previous.moments},
                  {"workList", m.workList},
                  {"outNear", next.nearLayer},
                  {"outFar", next.farLayer},
                  {"outMoments", next.moments},
                  {"outVariance", h.variance}},
                 Grid::indirect(m.workList), temporalPush);
  steps.dispatch(spatial_,
                 {{"workList", m.workList},
                  {"rays", m.rays},
                  {"layerCoc", h.layerCoc},
                  {"historyNear", next.nearLayer},
                  {"historyFar", next.farLayer},
                  {"historyMoments", next.moments},
                  {"variance", h.variance},
                  {"outNear", h.reconstructedNear},
                  {"outFar", h.reconstructedFar},
                  {"postProcess", images.dof.output},
                  {"outDifference", h.difference},
                  {"dilatedTiles", images.dof.dilatedTiles},
                  {"farTiles", m.farTiles}},
                 Grid::indirect(m.workList));
  if (view_ == DebugView::Final || view_ == DebugView::FocusZone) {
    // The post-process's colour where the mask did not trace; the composite the rest. Taking
    // turns, the pixels not listed keep the last frame's colour.
    if (!inTurns_)
      steps.step("hybrid_composite_copy",
                 [&](VkCommandBuffer cmd) { gpu::copyImage(cmd, images.dof.output, h.output); });
    steps.dispatch(moved_ ? compositeMoving_ : composite_,
                   {{"rays", m.rays},
                    {"sharp", g.color},
                    {"samplesAveraged", g.samplesAveraged},
                    {"specular", g.specular},
                    {"normalDepth", g.normalDepth},
                    {"postProcess", images.dof.output},
                    {"historyNear", h.reconstructedNear},
                    {"historyFar", h.reconstructedFar},
                    {"outColor", h.output},
                    {"workList", m.workList},
                    {"farTiles", m.farTiles},
                    {"difference", h.difference}},
                   Grid::indirect(m.workList));
  } else {
    steps.dispatch(debugView_,
                   {{"rays", m.rays},
                    {"normalDepth", g.normalDepth},
                    {"historyNear", h.reconstructedNear},
                    {"historyFar", h.reconstructedFar},
                    {"outColor", h.output}},
                   Grid::over(h.output), static_cast<uint32_t>(view_), "hybrid_composite");
  }
  // The in-focus zone is drawn over the finished image rather than in place of it.
  if (view_ == DebugView::FocusZone)
    steps.dispatch(focusZone_, {{"normalDepth", g.normalDepth}, {"color", h.output}},
                   Grid::over(h.output));
}

void HybridDof::advance() {
  if (changed_) current_ ^= 1u;
  hasHistory_ = true;
  lastDrewFinal_ = view_ == DebugView::Final;
}

}  // namespace hdof
