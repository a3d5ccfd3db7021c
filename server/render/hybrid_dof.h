// The hybrid depth of field (Tan, Chua, Biette, Bhojan 2020) after the G-buffer and the
// post-process: the adaptive ray mask (ray_mask.h), then the selective ray trace over its work
// list, temporal accumulation, spatial reconstruction and the composite (or a debug view),
// shaders/hybrid_*.comp. Keeps which history set is current; the images are the frame's.
#pragma once

#include "render/frame_images.h"
#include "render/modes.h"
#include "render/ray_mask.h"

#include <shared/frame.h>

namespace hdof {

class HybridDof {
 public:
  HybridDof(const gpu::Context& context, const GpuScene& scene);

  // Forgets the history: the next frame starts the accumulation over (a cut, a new viewport).
  void resetHistory() {
    hasHistory_ = false;
    stillFrames_ = 0;
  }
  // Reads images.gbuffer and images.dof.output; writes images.mask and images.hybrid, the frame
  // in images.hybrid.output. The frame uniforms' samples per pixel cap the mask's rays.
  // startFrame() before record(): the frame's uniforms (how many frames the camera and lens have
  // rested before this one, so that the history may average over a longer window; whether they
  // changed), whether the ray mask's edges from the last hybrid frame stand (G-buffer and lens
  // unchanged), the view (other than Final: that debug view instead of the composite, FocusZone
  // over it) and traceEverywhere (a full mask: every pixel gets the full rays). advance(): once
  // the frame is submitted.
  void startFrame(const gpu::FrameUniforms& uniforms, bool maskEdgesStand, DebugView view,
                  bool traceEverywhere);
  void record(StepRecorder& steps, const FrameImages& images) const;
  void advance();
  // The history set the last frame wrote (images.hybrid.history[current()]).
  uint32_t current() const { return current_; }

 private:
  RayMask mask_;
  gpu::ComputeProgram trace_;
  gpu::ComputeProgram historyClear_;
  // hybrid_temporal.comp for frames in which the camera moved, those in which only the lens
  // changed, and the others.
  gpu::ComputeProgram temporalMoved_, temporalLens_, temporalStill_;
  gpu::ComputeProgram spatial_;
  // The composite of frames in which the camera did not move, and of those in which it did.
  gpu::ComputeProgram composite_, compositeMoving_;
  gpu::ComputeProgram debugView_, focusZone_;
  bool hasHistory_ = false;
  uint32_t current_ = 0;      // the history set the last frame wrote
  uint32_t stillFrames_ = 0;  // frames since the camera or the lens last changed
  bool moved_ = true;         // this frame's camera differs from the last one's
  bool changed_ = true;       // ... or its lens does
  bool maskEdgesStand_ = false;
  DebugView view_ = DebugView::Final;
  bool traceEverywhere_ = false;
  bool lastDrewFinal_ = false;  // the last frame's output is the composite over every pixel
  // A resting view after such a frame: pixels take their rays in turns (ray_mask_rays.comp), and
  // those not listed keep their history and their last colour.
  bool inTurns_ = false;
};

}  // namespace hdof
