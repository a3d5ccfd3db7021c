#include "net/render_loop.h"

#include "render/focus_pick.h"

#include <malloc.h>

namespace hdof::net {

RenderLoop::RenderLoop(const gpu::Context& context, const Scene& scene, const GpuScene& gpuScene,
                       const Bvh& bvh, Metrics& metrics)
    : context_(context), scene_(scene), gpuScene_(gpuScene), bvh_(bvh), metrics_(metrics) {}

RenderLoop::~RenderLoop() { stop(); }

void RenderLoop::start(FrameSink onFrame, FailureSink onFailure) {
  onFrame_ = std::move(onFrame);
  onFailure_ = std::move(onFailure);
  thread_ = std::thread([this] { run(); });
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

void RenderLoop::frameDropped(uint64_t session, uint32_t frame) {
  {
    std::lock_guard lock(mutex_);
    if (auto it = sessions_.find(session); it != sessions_.end())
      it->second.state.frameDropped(frame);
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
    Clock::time_point now, std::optional<Clock::time_point>& nextDue) {
  auto start = sessions_.upper_bound(lastServed_);
  for (size_t i = 0; i < sessions_.size(); ++i, ++start) {
    if (start == sessions_.end()) start = sessions_.begin();
    std::optional<Clock::time_point> due = start->second.state.nextFrameDue();
    if (!due) continue;
    if (*due <= now) return start;
    if (!nextDue || *due < *nextDue) nextDue = due;
  }
  return sessions_.end();
}

void RenderLoop::run() {
  FocusPicker pickFocus = [this](const Camera& camera, Viewport viewport, float x, float y) {
    return depthUnderPixel(bvh_, camera, viewport.width, viewport.height, x, y);
  };
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    freeRemovedSessions(lock);
    if (stopping_) break;
    Clock::time_point now = Clock::now();
    std::optional<Clock::time_point> nextDue;
    auto due = pickDue(now, nextDue);
    if (due == sessions_.end()) {
      if (nextDue)
        wake_.wait_until(lock, *nextDue);
      else
        wake_.wait(lock);
      continue;
    }
    uint64_t id = due->first;
    Session& session = due->second;
    lastServed_ = id;
    FramePlan plan = session.state.startFrame(now, pickFocus);
    uint64_t coalesced = session.state.inputsCoalesced();
    metrics_.inputsCoalesced(coalesced - session.coalescedReported);
    session.coalescedReported = coalesced;
    lock.unlock();
    render(id, session, plan);  // the entry stays: only this thread erases entries
    lock.lock();
  }
}

void RenderLoop::render(uint64_t id, Session& session, const FramePlan& plan) {
  try {
    const FrameSettings& size = plan.request.settings;
    if (!session.pipeline)
      session.pipeline =
          std::make_unique<FramePipeline>(context_, scene_, gpuScene_, size.width, size.height);
    session.pipeline->resize(size.width, size.height);
    if (plan.resetHistory) session.pipeline->resetHistory();
    StreamFrame frame;
    frame.session = id;
    frame.plan = plan;
    frame.stats = session.pipeline->render(plan.request);
    frame.image = session.pipeline->image();
    frame.renderedAt = Clock::now();
    metrics_.frameRendered(frame.stats.passMs);
    onFrame_(std::move(frame));
  } catch (const std::exception& e) {
    session.pipeline.reset();
    {
      std::lock_guard lock(mutex_);
      session.removed = true;
    }
    onFailure_(id, e.what());
  }
}

}  // namespace hdof::net
