#include "net/render_loop.h"

#include "gpu/check.h"
#include "net/server_messages.h"
#include "render/focus_pick.h"

#include <malloc.h>
#include <algorithm>

namespace hdof::net {
namespace {

// The idle render thread still comes round its loop this often, so that its heartbeat shows it
// is alive.
constexpr auto kIdleBeat = std::chrono::seconds(1);
// A session's frames whose steps are timed: one in this many. Timestamps cost a software device
// a few percent of a frame; the stats and metrics need them only now and then.
constexpr uint32_t kTimedFrameInterval = 8;

}  // namespace

RenderLoop::RenderLoop(const gpu::Context& context, const Scene& scene, const GpuScene& gpuScene,
                       const Bvh& bvh, Metrics& metrics, double stallS, RenderFault fault)
    : context_(context),
      scene_(scene),
      gpuScene_(gpuScene),
      bvh_(bvh),
      metrics_(metrics),
      stallS_(stallS),
      fault_(fault) {}

RenderLoop::~RenderLoop() { stop(); }

void RenderLoop::start(FrameSink onFrame, FailureSink onFailure) {
  onFrame_ = std::move(onFrame);
  onFailure_ = std::move(onFailure);
  beat();
  threadRunning_ = true;
  thread_ = std::thread([this] { run(); });
}

void RenderLoop::beat() { heartbeat_ = Clock::now().time_since_epoch().count(); }

RenderHealth RenderLoop::health() const {
  RenderHealth health;
  health.threadRunning = threadRunning_;
  Clock::time_point beatAt{Clock::duration(heartbeat_.load())};
  health.heartbeatAgeS = std::chrono::duration<double>(Clock::now() - beatAt).count();
  health.stalled = health.threadRunning && health.heartbeatAgeS > stallS_;
  health.deviceLost = deviceLost_;
  std::lock_guard lock(mutex_);
  health.failure = failure_;
  return health;
}

void RenderLoop::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  sessions_.clear();  // the pipelines wait for the device in their destructors
}

void RenderLoop::addSession(uint64_t session, const SessionDefaults& defaults, Viewport viewport) {
  {
    std::lock_guard lock(mutex_);
    sessions_.insert_or_assign(session, Session{SessionState(defaults, viewport)});
  }
  wake_.notify_all();
}

std::optional<ProtocolError> RenderLoop::apply(uint64_t session, const ClientMessage& message,
                                               Clock::time_point received) {
  std::optional<ProtocolError> error;
  {
    std::lock_guard lock(mutex_);
    auto it = sessions_.find(session);
    if (it == sessions_.end() || it->second.removed) return std::nullopt;
    error = it->second.state.apply(message, received);
  }
  wake_.notify_all();
  return error;
}

std::variant<std::string, ProtocolError> RenderLoop::pick(uint64_t session,
                                                          const PickMessage& pick) {
  Camera camera;
  Lens lens;
  Viewport viewport;
  {
    std::lock_guard lock(mutex_);
    auto it = sessions_.find(session);
    if (it == sessions_.end() || it->second.removed) return pickedMessage(pick.id, std::nullopt);
    if (auto error = it->second.state.checkPixel("pick", pick.x, pick.y)) return *error;
    camera = it->second.state.camera();
    lens = it->second.state.lens();
    viewport = it->second.state.viewport();
  }
  // The BVH is never written after start-up: the render thread may read it at the same time.
  return pickedMessage(pick.id, surfaceUnderPixel(bvh_, camera, lens, viewport.width,
                                                  viewport.height, pick.x, pick.y));
}

void RenderLoop::frameDropped(uint64_t session, uint32_t frame) {
  {
    std::lock_guard lock(mutex_);
    if (auto it = sessions_.find(session); it != sessions_.end())
      it->second.state.frameDropped(frame);
  }
  wake_.notify_all();
}

void RenderLoop::frameSent(uint64_t session, uint32_t frame) {
  {
    std::lock_guard lock(mutex_);
    if (auto it = sessions_.find(session); it != sessions_.end()) it->second.state.frameSent(frame);
  }
  wake_.notify_all();
}

void RenderLoop::setSendBlocked(uint64_t session, bool blocked) {
  {
    std::lock_guard lock(mutex_);
    if (auto it = sessions_.find(session); it != sessions_.end())
      it->second.state.setSendBlocked(blocked);
  }
  wake_.notify_all();
}

void RenderLoop::removeSession(uint64_t session) {
  {
    std::lock_guard lock(mutex_);
    if (auto it = sessions_.find(session); it != sessions_.end()) it->second.removed = true;
  }
  wake_.notify_all();
}

void RenderLoop::freeRemovedSessions(std::unique_lock<std::mutex>& lock) {
  std::vector<std::unique_ptr<FramePipeline>> freed;
  for (auto it = sessions_.begin(); it != sessions_.end();) {
    if (!it->second.removed) {
      ++it;
      continue;
    }
    freed.push_back(std::move(it->second.pipeline));
    it = sessions_.erase(it);
  }
  if (freed.empty()) return;
  lock.unlock();
  freed.clear();
  // A pipeline's images and buffers are freed into the allocator's per-thread arenas; hand the
  // pages back, or the daemon's RSS steps up with every session that replaces another.
  malloc_trim(0);
  lock.lock();
}

std::map<uint64_t, RenderLoop::Session>::iterator RenderLoop::pickDue(
    Clock::time_point now, bool interactiveOnly, std::optional<Clock::time_point>& nextDue) {
  auto start = sessions_.upper_bound(lastServed_);
  for (size_t i = 0; i < sessions_.size(); ++i, ++start) {
    if (start == sessions_.end()) start = sessions_.begin();
    if (interactiveOnly && !start->second.state.interactive(now)) continue;
    std::optional<Clock::time_point> due = start->second.state.nextFrameDue();
    if (!due) continue;
    if (*due <= now) return start;
    if (!nextDue || *due < *nextDue) nextDue = due;
  }
  return sessions_.end();
}

void RenderLoop::run() {
  std::string failure;
  try {
    loop();
    return;
  } catch (const std::exception& e) {
    failure = e.what();
  } catch (...) {
    failure = "unknown exception";
  }
  // The thread is gone: /healthz fails from now on, and every session learns it cannot be served.
  std::vector<uint64_t> sessions;
  {
    std::lock_guard lock(mutex_);
    failure_ = "the render thread stopped: " + failure;
    threadRunning_ = false;
    for (auto& [id, session] : sessions_)
      if (!session.removed) {
        session.removed = true;
        sessions.push_back(id);
      }
  }
  for (uint64_t id : sessions) onFailure_(id, "the render thread stopped: " + failure);
}

void RenderLoop::loop() {
  FocusPicker pickFocus = [this](const Camera& camera, const Lens& lens, Viewport viewport,
                                 float x, float y) {
    return depthUnderPixel(bvh_, camera, lens, viewport.width, viewport.height, x, y);
  };
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    beat();
    freeRemovedSessions(lock);
    if (stopping_) break;
    Clock::time_point now = Clock::now();
    // The sessions whose frames answer input take turns on the device, each with its share of
    // 1 / target_fps (SessionState::shareDevice); the others wait for them.
    auto interacting =
        uint32_t(std::count_if(sessions_.begin(), sessions_.end(), [&](const auto& entry) {
          return !entry.second.removed && entry.second.state.interactive(now);
        }));
    metrics_.setSessionsInteractive(int(interacting));
    std::optional<Clock::time_point> nextDue;
    auto due = pickDue(now, interacting > 0, nextDue);
    if (due == sessions_.end()) {
      Clock::time_point tick = now + kIdleBeat;
      wake_.wait_until(lock, nextDue ? std::min(*nextDue, tick) : tick);
      continue;
    }
    if (fault_ == RenderFault::ThreadExit)
      throw std::runtime_error("injected fault (HDOF_FAULT=render-thread-exit)");
    uint64_t id = due->first;
    Session& session = due->second;
    lastServed_ = id;
    if (auto cost = movingMsPerPixel_.find(session.state.mode()); cost != movingMsPerPixel_.end())
      session.state.seedCost(cost->second);  // until the session has measured its own
    session.state.shareDevice(interacting);
    FramePlan plan = session.state.startFrame(now, pickFocus);
    uint64_t coalesced = session.state.inputsCoalesced();
    metrics_.inputsCoalesced(coalesced - session.coalescedReported);
    session.coalescedReported = coalesced;
    lock.unlock();
    std::optional<Rendered> rendered = render(id, session, plan);
    lock.lock();  // the entry stays: only this thread erases entries
    if (!rendered || session.removed) continue;
    session.state.frameRendered(rendered->ms, rendered->rasterDrawn);
    const FrameSettings& size = plan.request.settings;
    if (plan.moving && !plan.lensOnly)
      movingMsPerPixel_[plan.request.mode] = rendered->ms / (double(size.width) * size.height);
  }
}

std::optional<RenderLoop::Rendered> RenderLoop::render(uint64_t id, Session& session,
                                                       const FramePlan& plan) {
  try {
    if (fault_ == RenderFault::Stall) {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stopping_; });
      throw std::runtime_error("injected fault (HDOF_FAULT=render-stall)");
    }
    const FrameSettings& size = plan.request.settings;
    if (!session.pipeline)
      session.pipeline =
          std::make_unique<FramePipeline>(context_, scene_, gpuScene_, size.width, size.height);
    session.pipeline->resize(size.width, size.height);
    if (plan.resetHistory) session.pipeline->resetHistory();
    StreamFrame frame;
    frame.session = id;
    frame.plan = plan;
    FrameRequest request = plan.request;
    request.timePasses = session.framesSinceTimed == 0 || session.timedMode != request.mode;
    frame.stats = session.pipeline->render(request);
    if (fault_ == RenderFault::DeviceLost)  // as a submit or fence wait would report it
      throw VulkanError(VK_ERROR_DEVICE_LOST, "injected fault (HDOF_FAULT=device-lost)");
    frame.image = session.pipeline->image();
    frame.renderedAt = Clock::now();
    metrics_.frameRendered(frame.stats.passMs);  // empty for an untimed frame
    if (request.timePasses) {
      session.framesSinceTimed = 0;
      session.timedMode = request.mode;
      session.timedPassMs = frame.stats.passMs;
      session.timedGpuMs = frame.stats.gpuMs;
    } else {
      frame.stats.passMs = session.timedPassMs;
      frame.stats.gpuMs = session.timedGpuMs;
    }
    session.framesSinceTimed = (session.framesSinceTimed + 1) % kTimedFrameInterval;
    Rendered rendered{frame.stats.wallMs, frame.stats.rasterDrawn};
    onFrame_(std::move(frame));
    return rendered;
  } catch (const std::exception& e) {
    bool lost = false;
    if (const auto* vulkan = dynamic_cast<const VulkanError*>(&e))
      lost = vulkan->result == VK_ERROR_DEVICE_LOST;
    session.pipeline.reset();
    std::vector<uint64_t> failed = {id};
    {
      std::lock_guard lock(mutex_);
      session.removed = true;
      if (lost) {
        // Nothing renders on a lost device: every session ends, and /healthz fails.
        deviceLost_ = true;
        failure_ = std::string("the device was lost: ") + e.what();
        for (auto& [other, entry] : sessions_)
          if (other != id && !entry.removed) {
            entry.removed = true;
            failed.push_back(other);
          }
      }
    }
    for (uint64_t failedId : failed) onFailure_(failedId, e.what());
  }
  return std::nullopt;
}

}  // namespace hdof::net
