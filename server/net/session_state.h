// One session's view and streaming state, without GPU or network: it applies the client's
// messages (the newest camera and lens win), decides when the next frame is due and describes
// what that frame renders. Frames are due on a change, while ray-traced modes accumulate, and
// once more at still JPEG quality when the view comes to rest; never while max_unacked_frames
// frames wait for an ack, never while the connection cannot take more (sendBlocked), never faster
// than max_fps. Otherwise the session idles. Only frames sent can be acked: a frame counts as
// sent when the server has written it to the connection (frameSent). While the view moves, frames
// render at a lower scale when that is what holds target_fps (interactive resolution, from the
// render times reported by frameRendered, and with the device's time shared among the
// interactive sessions); a resting view renders at full size.
#pragma once

#include "net/protocol.h"
#include "render/frame_pipeline.h"

#include <algorithm>
#include <chrono>
#include <deque>
#include <functional>

namespace hdof::net {

using Clock = std::chrono::steady_clock;

struct StreamSettings {
  int jpegQualityMoving = 60, jpegQualityStill = 90;
  double maxFps = 60.0;
  uint32_t raysPerPixel = 1;
  float resolutionScale = 1.0f;
};

struct SessionDefaults {
  RenderMode mode = RenderMode::Hybrid;
  StreamSettings stream;
  uint32_t accumulationFrames = 64;  // raytrace, hybrid: frames of a still view, then idle
  double stillAfterMs = 150.0;       // no change for this long: the view rests
  double targetFps = 20.0;           // frames/s a moving view is scaled down to hold (0: never)
  uint32_t maxUnackedFrames = 2;
  Camera camera;  // the starting view
  Lens lens;
};

// One frame to render and what its message says about it.
struct FramePlan {
  uint32_t frame = 0;
  FrameRequest request;
  bool resetHistory = false;  // the mode changed: start the temporal history over
  uint32_t seq = 0;           // the last input seq applied
  std::optional<Clock::time_point> inputReceived;  // when the newest input it applies came in
  int jpegQuality = 90;
  uint32_t accumulatedFrames = 0;   // frames of this view so far, this one included
  uint32_t accumulationTarget = 0;  // frames of a still view, after which it has converged
  bool moving = false;              // the view changed within still_after_ms
  bool lensOnly = false;            // ... the lens alone (a focus pull, the aperture)
  float renderScale = 1.0f;  // the frame's size over the viewport's (resolution_scale, and lower
                             // while moving to hold target_fps)
};

// The distance to focus at for a viewport pixel (the depth of the surface under it), or nothing.
using FocusPicker =
    std::function<std::optional<float>(const Camera&, const Lens&, Viewport, float x, float y)>;

class SessionState {
 public:
  SessionState(const SessionDefaults& defaults, Viewport viewport);

  // Applies a validated message received at `received`. An error when it does not fit this
  // session (a pixel outside the viewport, an ack of a frame not yet sent); the state is unchanged.
  std::optional<ProtocolError> apply(const ClientMessage& message, Clock::time_point received);

  // When the next frame may start, or nothing while the session idles (a message or an ack
  // may change that).
  std::optional<Clock::time_point> nextFrameDue() const;
  // Whether the session's frames answer input at `now`: its first frame, or a change to show (a
  // move, a focus pull, a new still quality) or the still frame at rest after moving frames, with
  // its newest input within kInteractiveMs (a client that sends a change and then stops acking
  // its frames does not hold up the others for long). Its other frames refine a resting view (an
  // accumulation), and wait while any session is interactive (RenderLoop).
  bool interactive(Clock::time_point now) const;
  static constexpr double kInteractiveMs = 1000.0;
  // Takes what the next frame renders; the frame counts as in flight until acked or dropped.
  FramePlan startFrame(Clock::time_point now, const FocusPicker& pickFocus);
  // A started frame that will never be sent (its encode failed, it was dropped from a full queue).
  void frameDropped(uint32_t frame);
  // The server wrote this frame to the connection: acks up to it are valid now.
  void frameSent(uint32_t frame);
  // How long the frame last started took to render (submit to finish): moving frames teach the
  // interactive resolution what a pixel costs (until one has, another session's moving frames in
  // this mode, from seedCost, else this session's still frames); lens-only frames, and until one
  // has, still frames, what a lens change costs, unless they drew the raster (the first frames
  // at a new size, which pass).
  void frameRendered(double renderMs, bool rasterDrawn = false);
  void seedCost(double msPerPixel);
  // The interactive sessions (this one included), served in turns by one device: a moving
  // frame's budget is this share of 1 / target_fps, so that each of them holds target_fps.
  void shareDevice(uint32_t sessions) { sharers_ = std::max(sessions, 1u); }
  // While set, no frame is due: the connection's socket is choked or its outgoing list is full.
  void setSendBlocked(bool blocked) { sendBlocked_ = blocked; }
  bool sendBlocked() const { return sendBlocked_; }

  size_t framesInFlight() const { return inFlight_.size(); }
  uint64_t inputsCoalesced() const { return inputsCoalesced_; }
  // A resting view's size: the viewport's times resolution_scale.
  Viewport renderSize() const;
  const Lens& lens() const { return lens_; }
  RenderMode mode() const { return mode_; }
  // The newest camera received (what a pick looks through) and the session's viewport.
  const Camera& camera() const { return camera_; }
  Viewport viewport() const { return viewport_; }
  // An error naming the field when pixel (x, y) of a `what` message is outside the viewport.
  std::optional<ProtocolError> checkPixel(const char* what, float x, float y) const;

 private:
  // Frames a view renders while it rests (the mode's accumulation), then the session idles.
  uint32_t framesOfAStillView() const;
  // A frame is due as soon as flow control allows: a change, a focus pull, a frame of the view as
  // it stands (reshow_), or an accumulation still running.
  bool changing() const;
  static constexpr uint32_t kRasterRefineFrames = gpu::kStillRasterFrames;
  // The scale (of renderSize) a moving frame renders at: the largest step of kScaleStep, down
  // to kMinScale, whose predicted render time fits 1 / target_fps. It steps up only when the
  // larger step fits kScaleUpMargin of that, so that noisy frame times do not make every
  // frame another size (a new size reallocates the images and restarts the history).
  float interactiveScale();
  // The scale of a frame in which only the lens changed (a focus pull, the aperture): the last
  // frame's, whose raster stands at that size (only the DoF steps run; a new size would draw the
  // raster again), unless such frames (until one is timed, a still frame that reused the raster)
  // overrun 1 / target_fps there by more than kLensOverrun.
  float lensOnlyScale() const;
  static constexpr double kLensOverrun = 1.5;
  // What a frame may take to hold target_fps with the device's share (shareDevice).
  double frameBudgetMs() const { return 1000.0 / defaults_.targetFps / sharers_; }
  // The largest step of kScaleStep, down to kMinScale, at which frames costing msPerPixel for each
  // pixel of renderSize fit `ms`.
  float fittingScale(double msPerPixel, double ms) const;
  static constexpr float kScaleStep = 0.125f, kMinScale = 0.25f;
  static constexpr double kScaleUpMargin = 0.8;

  SessionDefaults defaults_;
  Viewport viewport_;
  StreamSettings stream_;
  RenderMode mode_;
  DebugView view_ = DebugView::Final;
  Camera camera_;
  Lens lens_;

  bool changed_ = true;  // something the image depends on changed since the last frame
  bool resetHistory_ = false;
  // One more frame of the view as it stands, its accumulation going on: jpeg_quality_still
  // changed, or an input changed nothing (its seq is answered).
  bool reshow_ = false;
  bool cameraPending_ = false, lensPending_ = false;  // not yet rendered: a newer one coalesces
  std::optional<FocusAtMessage> focusAt_;
  struct FocusPull {
    float from = 0.0f, to = 0.0f;
    Clock::time_point start;
    double durationMs = 0.0;
  };
  std::optional<FocusPull> pull_;

  uint32_t seq_ = 0;
  std::optional<Clock::time_point> newestInput_;  // not yet in a frame
  Clock::time_point lastInput_{};                 // the last message that changed something
  Clock::time_point lastMotion_{};                // the last camera, lens or focus change
  Clock::time_point lastCameraMotion_{};          // the last change of the view framed
  Clock::time_point lastFrameStart_{};
  bool lastFrameMoving_ = false, lastFrameLensOnly_ = false;
  float lastFrameScale_ = 1.0f;  // the last frame's size over renderSize's
  uint32_t lastFramePixels_ = 0;
  // Render time per pixel (0: unknown) of this session's moving frames (a moving average), of
  // another session's in this mode (seedCost), of this session's latest still frame, of its frames
  // in which the lens alone changed (a moving average), and of its latest still frame that reused
  // the raster (what a lens change costs, until one has been timed).
  double movingMsPerPixel_ = 0.0, seededMsPerPixel_ = 0.0, stillMsPerPixel_ = 0.0;
  double lensMsPerPixel_ = 0.0, restingMsPerPixel_ = 0.0;
  float movingScale_ = 1.0f;  // the scale of the last moving frame
  uint32_t sharers_ = 1;      // shareDevice
  uint32_t accumulated_ = 0;
  uint32_t lastFrame_ = 0;  // the last frame started
  uint32_t lastSent_ = 0;   // the newest frame written to the connection
  bool sendBlocked_ = false;
  uint32_t frameIndex_ = 0;
  struct InFlight {
    uint32_t frame = 0;
    bool sent = false;
  };
  std::deque<InFlight> inFlight_;  // started, neither acked nor dropped
  uint64_t inputsCoalesced_ = 0;
};

// The camera a message describes; near and far planes from `base`.
Camera cameraOf(const CameraMessage& message, const Camera& base);
Lens lensOf(const LensMessage& message);

}  // namespace hdof::net
