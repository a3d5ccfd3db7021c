// The render thread. It owns every session's frame pipeline over the scene all sessions share
// (one Vulkan queue, submitted to from this thread only), renders the sessions whose next frame
// is due in turn (round robin), and blocks on a condition variable while none is: no frames and
// no CPU for still, converged views. It wakes at least once a second to beat its heartbeat, which
// health() reports with the device's state for /healthz.
#pragma once

#include "encode/jpeg_pool.h"
#include "net/metrics.h"
#include "net/session_state.h"

#include <atomic>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <variant>

namespace hdof::net {

// One frame on its way to the client: rendered here, encoded on the JPEG pool, sent by the server.
struct StreamFrame {
  uint64_t session = 0;
  FramePlan plan;
  FrameStats stats;
  Clock::time_point renderedAt;
  ImageRgba8 image;  // until encoded
  EncodedJpeg jpeg;
};

// Faults the tests inject (HDOF_FAULT in hdof serve's environment) to see the daemon report them.
enum class RenderFault {
  None,
  ThreadExit,  // the render thread fails outside any frame when the first frame is due
  Stall,       // the first frame never finishes (until stop())
  DeviceLost,  // the first frame fails as if the device were lost
};

// What /healthz says about rendering.
struct RenderHealth {
  bool threadRunning = false;  // false once the render thread has died (or before start())
  bool stalled = false;        // running, but its heartbeat is older than the stall limit
  double heartbeatAgeS = 0.0;  // since the thread last came round its loop
  bool deviceLost = false;
  std::string failure;  // why the thread died or the device was lost
  bool ok() const { return threadRunning && !stalled && !deviceLost; }
};

class RenderLoop {
 public:
  using FrameSink = std::function<void(StreamFrame)>;  // on the render thread
  using FailureSink = std::function<void(uint64_t session, const std::string& why)>;

  // stallS: a frame (or the loop's idle tick) taking longer than this makes the thread count as
  // stalled in health().
  RenderLoop(const gpu::Context& context, const Scene& scene, const GpuScene& gpuScene,
             const Bvh& bvh, Metrics& metrics, double stallS = 30.0,
             RenderFault fault = RenderFault::None);
  ~RenderLoop();  // stop()
  RenderLoop(const RenderLoop&) = delete;
  RenderLoop& operator=(const RenderLoop&) = delete;

  void start(FrameSink onFrame, FailureSink onFailure);
  // Joins the render thread and frees every pipeline.
  void stop();

  // Any thread:
  void addSession(uint64_t session, const SessionDefaults& defaults, Viewport viewport);
  std::optional<ProtocolError> apply(uint64_t session, const ClientMessage& message,
                                     Clock::time_point received);
  // Where the surface under a pick's pixel is, in the session's newest camera (a CPU ray on the
  // BVH: the caller's thread, no frame): the `picked` message's text, or an error.
  std::variant<std::string, ProtocolError> pick(uint64_t session, const PickMessage& pick);
  void frameDropped(uint64_t session, uint32_t frame);
  // The server wrote the frame to the session's connection (acks up to it become valid).
  void frameSent(uint64_t session, uint32_t frame);
  // The session's connection cannot take more frames now (socket choked, outgoing list full).
  void setSendBlocked(uint64_t session, bool blocked);
  // The session's pipeline is freed on the render thread, after a frame it may be rendering.
  void removeSession(uint64_t session);
  RenderHealth health() const;

 private:
  struct Session {
    SessionState state;
    std::unique_ptr<FramePipeline> pipeline;  // render thread only
    bool removed = false;
    uint64_t coalescedReported = 0;
    // The steps of one frame in kTimedFrameInterval are timed (and the first in a new mode); the
    // others carry the latest timed frame's figures.
    uint32_t framesSinceTimed = 0;
    std::optional<RenderMode> timedMode;
    std::vector<std::pair<std::string, double>> timedPassMs;
    double timedGpuMs = 0.0;
  };
  void run();
  void loop();
  void beat();
  void freeRemovedSessions(std::unique_lock<std::mutex>& lock);
  // The next session due now (round robin after the last one served), or the time one is due.
  // While any session is interactive (SessionState::interactive), only such sessions are: a frame
  // that refines a resting view (full size, the longest a session renders) waits until no view
  // moves, where it would hold up every moving session's next frame.
  std::map<uint64_t, Session>::iterator pickDue(Clock::time_point now, bool interactiveOnly,
                                                std::optional<Clock::time_point>& nextDue);
  // Renders the plan and hands the frame on; returns its render time (submit to finish) and
  // whether it drew the raster, or nothing when the session failed.
  struct Rendered {
    double ms = 0.0;
    bool rasterDrawn = false;
  };
  std::optional<Rendered> render(uint64_t id, Session& session, const FramePlan& plan);

  const gpu::Context& context_;
  const Scene& scene_;
  const GpuScene& gpuScene_;
  // The latest moving frame's render time per pixel, by mode (any session): a new session's
  // first moving frame is scaled by it (SessionState::seedCost).
  std::map<RenderMode, double> movingMsPerPixel_;
  const Bvh& bvh_;
  Metrics& metrics_;
  const double stallS_;
  RenderFault fault_;
  FrameSink onFrame_;
  FailureSink onFailure_;

  std::atomic<int64_t> heartbeat_{0};  // Clock ticks of the last beat
  std::atomic<bool> threadRunning_{false};
  std::atomic<bool> deviceLost_{false};

  mutable std::mutex mutex_;
  std::string failure_;  // under mutex_
  std::condition_variable wake_;
  bool stopping_ = false;
  std::map<uint64_t, Session> sessions_;  // entries are erased on the render thread only
  uint64_t lastServed_ = 0;
  std::thread thread_;
};

}  // namespace hdof::net
