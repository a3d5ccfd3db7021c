#include "net/session_state.h"

#include <algorithm>
#include <cmath>

namespace hdof::net {
namespace {

double msBetween(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double, std::milli>(to - from).count();
}

Clock::duration msDuration(double ms) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::milli>(ms));
}

// A size times a scale, each side at least 16 pixels.
Viewport scaledSize(Viewport size, double scale) {
  auto side = [&](uint32_t pixels) {
    return std::max<uint32_t>(16, uint32_t(std::lround(pixels * scale)));
  };
  return {side(size.width), side(size.height)};
}

}  // namespace

Camera cameraOf(const CameraMessage& message, const Camera& base) {
  Camera camera = base;
  camera.position = message.position;
  camera.forward = glm::normalize(message.target - message.position);
  camera.up = glm::normalize(message.up - camera.forward * glm::dot(message.up, camera.forward));
  return camera;
}

Lens lensOf(const LensMessage& message) {
  Lens lens;
  lens.focalLengthMm = message.focalLengthMm;
  lens.fNumber = message.fNumber;
  lens.focusDistance = message.focusDistance;
  lens.blades = message.blades;
  lens.bladeRotation = glm::radians(message.bladeRotationDeg);
  lens.sensor = message.sensor;
  return lens;
}

SessionState::SessionState(const SessionDefaults& defaults, Viewport viewport)
    : defaults_(defaults),
      viewport_(viewport),
      stream_(defaults.stream),
      mode_(defaults.mode),
      camera_(defaults.camera),
      lens_(defaults.lens) {}

uint32_t SessionState::framesOfAStillView() const {
  if (mode_ == RenderMode::RayTrace || mode_ == RenderMode::Hybrid)
    return defaults_.accumulationFrames;
  // The raster modes refine too: their anti-aliasing has converged by then.
  return std::min(defaults_.accumulationFrames, kRasterRefineFrames);
}

float SessionState::interactiveScale() {
  // What a pixel of a moving frame costs: this session's moving frames, else another session's
  // in this mode, else this session's still frames.
  double msPerPixel = movingMsPerPixel_ > 0.0   ? movingMsPerPixel_
                      : seededMsPerPixel_ > 0.0 ? seededMsPerPixel_
                                                : stillMsPerPixel_;
  if (defaults_.targetFps <= 0.0 || msPerPixel <= 0.0) return 1.0f;
  double budgetMs = frameBudgetMs();
  float down = fittingScale(msPerPixel, budgetMs);
  float up = fittingScale(msPerPixel, kScaleUpMargin * budgetMs);
  if (down < movingScale_)
    movingScale_ = down;
  else if (up > movingScale_)
    movingScale_ = up;
  return movingScale_;
}

float SessionState::lensOnlyScale() const {
  double msPerPixel = lensMsPerPixel_ > 0.0 ? lensMsPerPixel_ : restingMsPerPixel_;
  if (defaults_.targetFps <= 0.0 || msPerPixel <= 0.0) return lastFrameScale_;
  double budgetMs = frameBudgetMs();
  // A smaller size draws the raster again (and gathers its samples anew): worth it only for an
  // overrun that makes the pull stutter.
  if (fittingScale(msPerPixel, kLensOverrun * budgetMs) >= lastFrameScale_) return lastFrameScale_;
  return std::min(lastFrameScale_, fittingScale(msPerPixel, budgetMs));
}

float SessionState::fittingScale(double msPerPixel, double ms) const {
  Viewport full = renderSize();
  double fullMs = msPerPixel * double(full.width) * double(full.height);
  if (fullMs <= ms) return 1.0f;
  // Render time goes with the pixels: the square of the scale.
  float scale = float(std::sqrt(ms / fullMs));
  return std::max(kMinScale, std::floor(scale / kScaleStep) * kScaleStep);
}

void SessionState::frameRendered(double renderMs, bool rasterDrawn) {
  if (lastFramePixels_ == 0) return;
  double perPixel = renderMs / double(lastFramePixels_);
  auto average = [&](double& msPerPixel) {
    msPerPixel = msPerPixel > 0.0 ? 0.7 * msPerPixel + 0.3 * perPixel : perPixel;
  };
  if (!lastFrameMoving_) {
    stillMsPerPixel_ = perPixel;
    if (!rasterDrawn) restingMsPerPixel_ = perPixel;
  } else if (!lastFrameLensOnly_)
    average(movingMsPerPixel_);
  else if (!rasterDrawn)
    average(lensMsPerPixel_);
}

void SessionState::seedCost(double msPerPixel) { seededMsPerPixel_ = msPerPixel; }

Viewport SessionState::renderSize() const {
  Viewport size = scaledSize(viewport_, stream_.resolutionScale);
  return {std::min(size.width, viewport_.width), std::min(size.height, viewport_.height)};
}

std::optional<ProtocolError> SessionState::checkPixel(const char* what, float x, float y) const {
  if (x < float(viewport_.width) && y < float(viewport_.height)) return std::nullopt;
  return ProtocolError{ErrorCode::OutOfRange,
                       std::string(what) + " pixel (" + std::to_string(int(x)) + ", " +
                           std::to_string(int(y)) + ") is outside the " +
                           std::to_string(viewport_.width) + "x" +
                           std::to_string(viewport_.height) + " viewport",
                       x >= float(viewport_.width) ? "x" : "y"};
}

std::optional<ProtocolError> SessionState::apply(const ClientMessage& message,
                                                 Clock::time_point received) {
  auto input = [&](uint32_t seq) {
    seq_ = seq;
    newestInput_ = received;
    lastInput_ = received;
    changed_ = true;
  };
  // An input that changes nothing (the same camera or lens again, as a client may send it with
  // every other change; the same mode) is answered by a frame that carries its seq and goes on
  // with the view as it stands (its accumulation is not started over). It is no new input for
  // the render loop (lastInput_): the same camera sent over and over does not make a resting
  // view's frames interactive.
  auto unchanged = [&](uint32_t seq) {
    seq_ = seq;
    newestInput_ = received;
    reshow_ = true;
    return std::nullopt;
  };
  if (const auto* camera = std::get_if<CameraMessage>(&message)) {
    Camera next = cameraOf(*camera, defaults_.camera);
    if (next == camera_) return unchanged(camera->seq);
    inputsCoalesced_ += cameraPending_;
    cameraPending_ = true;
    camera_ = next;
    lastMotion_ = lastCameraMotion_ = received;
    input(camera->seq);
  } else if (const auto* lens = std::get_if<LensMessage>(&message)) {
    Lens before = lens_;
    Lens next = lensOf(*lens);
    if (next == lens_ && !pull_ && !focusAt_) return unchanged(lens->seq);
    inputsCoalesced_ += lensPending_;
    lensPending_ = true;
    lens_ = next;
    pull_.reset();
    focusAt_.reset();
    lastMotion_ = received;
    // A new focal length or sensor frames another view: the raster is drawn again, as when the
    // camera moves.
    if (lens_.focalLengthMm != before.focalLengthMm || !(lens_.sensor == before.sensor))
      lastCameraMotion_ = received;
    input(lens->seq);
  } else if (const auto* focus = std::get_if<FocusAtMessage>(&message)) {
    if (auto error = checkPixel("focus_at", focus->x, focus->y)) return error;
    focusAt_ = *focus;
    input(focus->seq);
  } else if (const auto* mode = std::get_if<ModeMessage>(&message)) {
    if (mode->mode == mode_ && mode->view == view_) return unchanged(mode->seq);
    resetHistory_ = resetHistory_ || mode->mode != mode_;
    mode_ = mode->mode;
    view_ = mode->view;
    input(mode->seq);
  } else if (const auto* settings = std::get_if<SettingsMessage>(&message)) {
    StreamSettings before = stream_;
    stream_.jpegQualityMoving = settings->jpegQualityMoving.value_or(stream_.jpegQualityMoving);
    stream_.jpegQualityStill = settings->jpegQualityStill.value_or(stream_.jpegQualityStill);
    stream_.maxFps = settings->maxFps.value_or(stream_.maxFps);
    stream_.raysPerPixel = settings->raysPerPixel.value_or(stream_.raysPerPixel);
    stream_.resolutionScale = settings->resolutionScale.value_or(stream_.resolutionScale);
    bool restart = stream_.raysPerPixel != before.raysPerPixel ||
                   stream_.resolutionScale != before.resolutionScale;
    // A resting view is shown again at its new quality (a snapshot asks for 100), continuing its
    // accumulation rather than starting it over.
    bool requalify = stream_.jpegQualityStill != before.jpegQualityStill;
    changed_ = changed_ || restart;
    reshow_ = reshow_ || requalify;
    if (restart || requalify) lastInput_ = received;
  } else if (const auto* ack = std::get_if<AckMessage>(&message)) {
    // Only what was written to the connection: an ack of a frame the client cannot have seen
    // would open the window for frames that pile up in the daemon.
    if (ack->frame > lastSent_)
      return ProtocolError{ErrorCode::OutOfRange,
                           "frame " + std::to_string(ack->frame) + " has not been sent", "frame"};
    // Acknowledges every earlier frame that was sent too; one still on its way (frames can
    // finish encoding out of order) stays in flight until it is sent and acked.
    std::erase_if(inFlight_, [&](const InFlight& f) { return f.sent && f.frame <= ack->frame; });
  } else if (const auto* pick = std::get_if<PickMessage>(&message)) {
    return checkPixel("pick", pick->x, pick->y);  // answered by the server; it changes nothing
  } else {
    return ProtocolError{ErrorCode::NotAllowed, "this session has already said hello", "type"};
  }
  return std::nullopt;
}

bool SessionState::changing() const {
  return changed_ || pull_ || reshow_ || accumulated_ < framesOfAStillView();
}

bool SessionState::interactive(Clock::time_point now) const {
  if (lastFrame_ == 0) return true;  // a new session's first frame
  bool answering = changed_ || pull_ || reshow_ || lastFrameMoving_;
  return answering && msBetween(std::max(lastInput_, lastMotion_), now) < kInteractiveMs;
}

std::optional<Clock::time_point> SessionState::nextFrameDue() const {
  if (sendBlocked_ || inFlight_.size() >= defaults_.maxUnackedFrames) return std::nullopt;
  Clock::time_point earliest = lastFrameStart_ + msDuration(1000.0 / stream_.maxFps);
  if (changing()) return earliest;
  // The view has come to rest after frames at moving quality: one at still quality.
  if (lastFrameMoving_) return std::max(earliest, lastMotion_ + msDuration(defaults_.stillAfterMs));
  return std::nullopt;
}

FramePlan SessionState::startFrame(Clock::time_point now, const FocusPicker& pickFocus) {
  if (focusAt_) {
    std::optional<float> distance = pickFocus(camera_, lens_, viewport_, focusAt_->x, focusAt_->y);
    if (distance && focusAt_->pullMs > 0.0f)
      pull_ = FocusPull{lens_.focusDistance, *distance, now, focusAt_->pullMs};
    else if (distance)
      lens_.focusDistance = *distance;
    lastMotion_ = now;
    focusAt_.reset();
  }
  if (pull_) {
    double t = std::clamp(msBetween(pull_->start, now) / pull_->durationMs, 0.0, 1.0);
    double eased = t * t * (3.0 - 2.0 * t);
    lens_.focusDistance = float(pull_->from + (pull_->to - pull_->from) * eased);
    lastMotion_ = now;
    changed_ = true;
    if (t >= 1.0) pull_.reset();
  }
  if (changed_) accumulated_ = 0;
  bool moving = msBetween(lastMotion_, now) < defaults_.stillAfterMs;
  bool lensOnly = moving && msBetween(lastCameraMotion_, now) >= defaults_.stillAfterMs;

  FramePlan plan;
  plan.frame = ++lastFrame_;
  Viewport size = renderSize();
  float scale = !moving ? 1.0f : lensOnly ? lensOnlyScale() : interactiveScale();
  if (scale < 1.0f) size = scaledSize(size, scale);
  plan.request.mode = mode_;
  plan.request.camera = camera_;
  plan.request.lens = lens_;
  plan.request.settings.width = size.width;
  plan.request.settings.height = size.height;
  plan.request.settings.frameIndex = frameIndex_++;
  plan.request.settings.samplesPerPixel = stream_.raysPerPixel;
  plan.request.view = view_;
  plan.resetHistory = resetHistory_;
  plan.seq = seq_;
  plan.inputReceived = newestInput_;
  plan.jpegQuality = moving ? stream_.jpegQualityMoving : stream_.jpegQualityStill;
  plan.accumulatedFrames = ++accumulated_;
  plan.accumulationTarget = framesOfAStillView();
  plan.moving = moving;
  plan.lensOnly = lensOnly;
  plan.renderScale = float(size.width) / float(viewport_.width);

  inFlight_.push_back({plan.frame, false});
  lastFrameStart_ = now;
  lastFrameMoving_ = moving;
  lastFrameLensOnly_ = lensOnly;
  lastFrameScale_ = scale;
  lastFramePixels_ = size.width * size.height;
  changed_ = resetHistory_ = cameraPending_ = lensPending_ = reshow_ = false;
  newestInput_.reset();
  return plan;
}

void SessionState::frameSent(uint32_t frame) {
  lastSent_ = std::max(lastSent_, frame);
  for (InFlight& f : inFlight_)
    if (f.frame == frame) f.sent = true;
}

void SessionState::frameDropped(uint32_t frame) {
  std::erase_if(inFlight_, [&](const InFlight& f) { return f.frame == frame; });
}

}  // namespace hdof::net
