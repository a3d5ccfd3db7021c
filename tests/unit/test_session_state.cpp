// A session's scheduling without GPU or network: frames on change, while accumulating and once
// at still quality when the view rests; never more than max_unacked_frames in flight, only sent
// frames can be acked, none while the connection is blocked; the newest camera wins; focus_at and
// the focus pull.
#include "net/session_state.h"

#include <gtest/gtest.h>

namespace hdof::net {
namespace {

using namespace std::chrono_literals;

const Clock::time_point kStart = Clock::now();

SessionDefaults defaults(RenderMode mode) {
  SessionDefaults d;
  d.mode = mode;
  d.accumulationFrames = 4;
  d.stillAfterMs = 100.0;
  d.stream.jpegQualityMoving = 50;
  d.stream.jpegQualityStill = 90;
  d.stream.maxFps = 1000.0;
  return d;
}

CameraMessage camera(uint32_t seq, float x) {
  CameraMessage c;
  c.seq = seq;
  c.position = {x, 0.0f, 5.0f};
  c.target = {x, 0.0f, 0.0f};
  return c;
}

std::optional<float> noFocus(const Camera&, const Lens&, Viewport, float, float) { return std::nullopt; }

// The server wrote the frame, then the client acked it.
std::optional<ProtocolError> sentAndAcked(SessionState& s, uint32_t frame, Clock::time_point t) {
  s.frameSent(frame);
  return s.apply(AckMessage{frame}, t);
}

// Frame `frame`, started at `at`, taking msPerPixel for each pixel it renders; sent and acked.
FramePlan frameTaking(SessionState& s, uint32_t frame, Clock::time_point at, double msPerPixel,
                      bool rasterDrawn = false) {
  FramePlan plan = s.startFrame(at, noFocus);
  s.frameRendered(msPerPixel * plan.request.settings.width * plan.request.settings.height,
                  rasterDrawn);
  sentAndAcked(s, frame, at);
  return plan;
}

bool dueAt(const SessionState& s, Clock::time_point t) {
  auto due = s.nextFrameDue();
  return due && *due <= t;
}

// The raster modes refine a still view too (anti-aliasing), for at most 16 frames.
TEST(SessionState, AStillRasterViewRefinesThenIdles) {
  SessionState s(defaults(RenderMode::PostProcess), {64, 48});
  ASSERT_TRUE(dueAt(s, kStart));
  FramePlan first = s.startFrame(kStart, noFocus);
  EXPECT_EQ(first.frame, 1u);
  EXPECT_EQ(first.jpegQuality, 90);
  EXPECT_FALSE(first.inputReceived);
  EXPECT_EQ(first.request.settings.width, 64u);
  ASSERT_FALSE(sentAndAcked(s, 1, kStart));
  for (uint32_t frame = 2; frame <= 4; ++frame) {
    ASSERT_TRUE(s.nextFrameDue()) << frame;
    EXPECT_EQ(s.startFrame(kStart, noFocus).accumulatedFrames, frame);
    sentAndAcked(s, frame, kStart);
  }
  EXPECT_FALSE(s.nextFrameDue()) << "idle once the view's frames are done (accumulation_frames 4)";
}

TEST(SessionState, NewestCameraWinsAndCarriesItsSeq) {
  SessionState s(defaults(RenderMode::PostProcess), {64, 48});
  s.startFrame(kStart, noFocus);
  sentAndAcked(s, 1, kStart);
  s.apply(camera(1, 1.0f), kStart + 1ms);
  s.apply(camera(2, 2.0f), kStart + 2ms);
  EXPECT_EQ(s.inputsCoalesced(), 1u);
  FramePlan plan = s.startFrame(kStart + 3ms, noFocus);
  EXPECT_EQ(plan.seq, 2u);
  EXPECT_EQ(plan.request.camera.position.x, 2.0f);
  EXPECT_EQ(plan.inputReceived, kStart + 2ms);
  EXPECT_EQ(plan.jpegQuality, 50) << "moving";
}

TEST(SessionState, AtMostMaxUnackedFramesInFlight) {
  SessionState s(defaults(RenderMode::RayTrace), {64, 48});
  s.startFrame(kStart, noFocus);
  s.startFrame(kStart + 1ms, noFocus);
  EXPECT_EQ(s.framesInFlight(), 2u);
  EXPECT_FALSE(s.nextFrameDue()) << "two frames without an ack";
  s.apply(camera(1, 1.0f), kStart + 2ms);
  EXPECT_FALSE(s.nextFrameDue()) << "a change does not lift the limit";
  sentAndAcked(s, 1, kStart + 3ms);
  EXPECT_TRUE(dueAt(s, kStart + 3ms));
  ProtocolError error = *s.apply(AckMessage{9}, kStart);
  EXPECT_EQ(error.field, "frame");
  s.frameDropped(2);
  EXPECT_EQ(s.framesInFlight(), 0u);
}

TEST(SessionState, OnlyFramesSentCanBeAcked) {
  // A client that acks frames it cannot have seen must not open the window: the frames would
  // pile up in the daemon.
  SessionState s(defaults(RenderMode::RayTrace), {64, 48});
  s.startFrame(kStart, noFocus);
  s.startFrame(kStart + 1ms, noFocus);
  std::optional<ProtocolError> early = s.apply(AckMessage{1}, kStart + 2ms);
  ASSERT_TRUE(early) << "frame 1 was started, not sent";
  EXPECT_EQ(early->code, ErrorCode::OutOfRange);
  EXPECT_EQ(early->field, "frame");
  EXPECT_FALSE(s.nextFrameDue()) << "the window stays closed";
  s.frameSent(1);
  EXPECT_TRUE(s.apply(AckMessage{2}, kStart + 3ms)) << "frame 2 is not sent yet";
  EXPECT_FALSE(s.apply(AckMessage{1}, kStart + 3ms));
  EXPECT_EQ(s.framesInFlight(), 1u);
}

TEST(SessionState, AnAckLeavesAnEarlierFrameNotYetSentInFlight) {
  // Encodes can finish out of order: frame 2 goes out before frame 1.
  SessionState s(defaults(RenderMode::RayTrace), {64, 48});
  s.startFrame(kStart, noFocus);
  s.startFrame(kStart + 1ms, noFocus);
  s.frameSent(2);
  ASSERT_FALSE(s.apply(AckMessage{2}, kStart + 2ms));
  EXPECT_EQ(s.framesInFlight(), 1u) << "frame 1 is still on its way";
  s.frameSent(1);
  ASSERT_FALSE(s.apply(AckMessage{1}, kStart + 3ms));
  EXPECT_EQ(s.framesInFlight(), 0u);
}

TEST(SessionState, NoFrameWhileTheConnectionIsBlocked) {
  SessionState s(defaults(RenderMode::PostProcess), {64, 48});
  s.setSendBlocked(true);
  EXPECT_FALSE(s.nextFrameDue()) << "the socket is choked or the outgoing list full";
  s.apply(camera(1, 1.0f), kStart);
  EXPECT_FALSE(s.nextFrameDue());
  s.setSendBlocked(false);
  EXPECT_TRUE(dueAt(s, kStart));
}

TEST(SessionState, RayTracedModesAccumulateThenIdle) {
  SessionState s(defaults(RenderMode::RayTrace), {64, 48});
  Clock::time_point t = kStart;
  for (uint32_t i = 1; i <= 4; ++i) {
    ASSERT_TRUE(dueAt(s, t)) << i;
    FramePlan plan = s.startFrame(t, noFocus);
    EXPECT_EQ(plan.accumulatedFrames, i);
    EXPECT_EQ(plan.accumulationTarget, 4u) << "the frames that converge it";
    sentAndAcked(s, plan.frame, t);
    t += 5ms;
  }
  EXPECT_FALSE(s.nextFrameDue()) << "converged";
  s.apply(camera(1, 1.0f), t);
  FramePlan moved = s.startFrame(t, noFocus);
  EXPECT_EQ(moved.accumulatedFrames, 1u) << "a change starts over";
  EXPECT_TRUE(moved.moving);
}

TEST(SessionState, ANewStillQualityShowsTheRestingViewOnceMore) {
  SessionState s(defaults(RenderMode::RayTrace), {64, 48});
  Clock::time_point t = kStart + 1s;
  for (uint32_t i = 1; i <= 4; ++i) {
    sentAndAcked(s, s.startFrame(t, noFocus).frame, t);
    t += 5ms;
  }
  ASSERT_FALSE(s.nextFrameDue()) << "converged";
  SettingsMessage settings;
  settings.jpegQualityStill = 100;
  s.apply(settings, t);
  ASSERT_TRUE(dueAt(s, t));
  FramePlan again = s.startFrame(t, noFocus);
  EXPECT_EQ(again.jpegQuality, 100);
  EXPECT_EQ(again.accumulatedFrames, 5u) << "the accumulation goes on";
  EXPECT_FALSE(again.moving);
  sentAndAcked(s, again.frame, t);
  EXPECT_FALSE(s.nextFrameDue()) << "then idle again";
}

TEST(SessionState, AStillQualityFrameOnceTheViewRests) {
  SessionDefaults d = defaults(RenderMode::PostProcess);
  d.accumulationFrames = 1;  // no refinement: the frame after the move is the still one
  SessionState s(d, {64, 48});
  s.startFrame(kStart, noFocus);
  sentAndAcked(s, 1, kStart);
  s.apply(camera(1, 1.0f), kStart + 10ms);
  FramePlan moving = s.startFrame(kStart + 11ms, noFocus);
  EXPECT_EQ(moving.jpegQuality, 50);
  sentAndAcked(s, moving.frame, kStart + 12ms);
  auto due = s.nextFrameDue();
  ASSERT_TRUE(due);
  EXPECT_EQ(*due, kStart + 110ms) << "still_after_ms after the last change";
  FramePlan still = s.startFrame(*due, noFocus);
  EXPECT_EQ(still.jpegQuality, 90);
  EXPECT_EQ(still.seq, 1u);
  EXPECT_FALSE(still.inputReceived);
  sentAndAcked(s, still.frame, *due);
  EXPECT_FALSE(s.nextFrameDue());
}

TEST(SessionState, MaxFpsSpacesFrames) {
  SessionDefaults d = defaults(RenderMode::RayTrace);
  d.stream.maxFps = 10.0;
  SessionState s(d, {64, 48});
  s.startFrame(kStart, noFocus);
  EXPECT_EQ(*s.nextFrameDue(), kStart + 100ms);
}

TEST(SessionState, FocusAtSetsTheFocusAndPullsSmoothly) {
  SessionState s(defaults(RenderMode::PostProcess), {64, 48});
  Viewport seen;
  auto pick = [&](const Camera&, const Lens&, Viewport viewport, float x, float y) -> std::optional<float> {
    seen = viewport;
    return x + y;
  };
  EXPECT_EQ(s.apply(FocusAtMessage{1, 64.0f, 0.0f}, kStart)->field, "x");
  EXPECT_EQ(s.apply(FocusAtMessage{1, 0.0f, 48.0f}, kStart)->field, "y");
  ASSERT_FALSE(s.apply(FocusAtMessage{1, 3.0f, 4.0f}, kStart));
  EXPECT_EQ(s.startFrame(kStart, pick).request.lens.focusDistance, 7.0f);
  EXPECT_EQ(seen.width, 64u);
  sentAndAcked(s, 1, kStart);

  ASSERT_FALSE(s.apply(FocusAtMessage{2, 10.0f, 7.0f, 1000.0f}, kStart + 1ms));
  EXPECT_EQ(s.startFrame(kStart + 1ms, pick).request.lens.focusDistance, 7.0f) << "pull starts";
  sentAndAcked(s, 2, kStart);
  ASSERT_TRUE(s.nextFrameDue()) << "frames while pulling";
  float middle = s.startFrame(kStart + 501ms, pick).request.lens.focusDistance;
  EXPECT_NEAR(middle, 12.0f, 1e-3f);
  sentAndAcked(s, 3, kStart);
  EXPECT_EQ(s.startFrame(kStart + 2s, pick).request.lens.focusDistance, 17.0f);
}

// While the camera moves, frames render at the scale whose predicted time (from the moving
// frames' render times, per pixel) fits 1 / target_fps, in steps of 1/8 down to 1/4; a resting
// view renders at full size again.
TEST(SessionState, AMovingViewRendersAtTheScaleThatHoldsTargetFps) {
  SessionDefaults d = defaults(RenderMode::PostProcess);
  d.targetFps = 20.0;  // 50 ms a frame
  SessionState s(d, {200, 100});
  s.apply(camera(1, 0.0f), kStart);
  FramePlan first = s.startFrame(kStart, noFocus);
  EXPECT_EQ(first.request.settings.width, 200u) << "no render time known yet";
  EXPECT_EQ(first.renderScale, 1.0f);
  s.frameRendered(200.0);  // 0.01 ms a pixel: the full size would take 200 ms
  sentAndAcked(s, 1, kStart);

  s.apply(camera(2, 1.0f), kStart + 10ms);
  FramePlan moving = s.startFrame(kStart + 10ms, noFocus);
  EXPECT_EQ(moving.request.settings.width, 100u) << "half the side: a quarter of the time";
  EXPECT_EQ(moving.request.settings.height, 50u);
  EXPECT_EQ(moving.renderScale, 0.5f);
  s.frameRendered(10000.0);  // much slower now
  sentAndAcked(s, 2, kStart);

  s.apply(camera(3, 2.0f), kStart + 20ms);
  FramePlan slower = s.startFrame(kStart + 20ms, noFocus);
  EXPECT_EQ(slower.renderScale, 0.25f) << "never below a quarter";
  EXPECT_EQ(slower.request.settings.width, 50u);
  sentAndAcked(s, 3, kStart);

  ASSERT_TRUE(s.nextFrameDue()) << "the view comes to rest";
  FramePlan resting = s.startFrame(kStart + 1s, noFocus);
  EXPECT_EQ(resting.request.settings.width, 200u) << "full size when still";
  EXPECT_EQ(resting.renderScale, 1.0f);
}

// A session's first moving frame is scaled too: by what another session's moving frames in its
// mode cost per pixel (seedCost), else by its own still frame's cost; once it has rendered a
// moving frame, its own moving frames decide.
TEST(SessionState, TheFirstMovingFrameIsScaledByTheBestCostKnown) {
  SessionDefaults d = defaults(RenderMode::PostProcess);
  d.targetFps = 20.0;  // 50 ms a frame; at 200x100, 0.01 ms a pixel takes 200 ms
  struct Case {
    double stillMsPerPixel;
    std::optional<double> seededMsPerPixel;
    float firstMovingScale;
  };
  for (Case c : {Case{0.01, std::nullopt, 0.5f}, Case{0.001, std::nullopt, 1.0f},
                 Case{0.001, 0.01, 0.5f}}) {
    SessionState s(d, {200, 100});
    ASSERT_FALSE(s.startFrame(kStart, noFocus).moving);
    s.frameRendered(c.stillMsPerPixel * 200 * 100);
    sentAndAcked(s, 1, kStart);
    if (c.seededMsPerPixel) s.seedCost(*c.seededMsPerPixel);
    s.apply(camera(2, 1.0f), kStart + 10ms);
    FramePlan moving = s.startFrame(kStart + 10ms, noFocus);
    ASSERT_TRUE(moving.moving);
    EXPECT_EQ(moving.renderScale, c.firstMovingScale) << c.stillMsPerPixel;
    s.frameRendered(0.001 * moving.request.settings.width * moving.request.settings.height);
    sentAndAcked(s, 2, kStart);
    s.seedCost(0.02);
    s.apply(camera(3, 2.0f), kStart + 20ms);
    EXPECT_EQ(s.startFrame(kStart + 20ms, noFocus).renderScale, 1.0f)
        << "its own moving frames decide once it has one";
  }
}

// Frame times that hover at a step's boundary keep the moving scale where it is (each new size
// reallocates the images and restarts the history); it steps up once the larger step fits with
// room to spare.
TEST(SessionState, TheMovingScaleStepsUpOnlyWithRoomToSpare) {
  SessionDefaults d = defaults(RenderMode::PostProcess);
  d.targetFps = 20.0;  // 50 ms a frame
  SessionState s(d, {200, 100});
  uint32_t frame = 0;
  // Moving frames that each take `msPerPixel` for every pixel they render.
  auto moveFor = [&](int frames, double msPerPixel) {
    FramePlan plan;
    for (int i = 0; i < frames; ++i) {
      auto at = kStart + std::chrono::milliseconds(10 * ++frame);
      s.apply(camera(frame, float(frame)), at);
      plan = frameTaking(s, frame, at, msPerPixel);
    }
    return plan.renderScale;
  };
  EXPECT_EQ(moveFor(2, 0.01), 0.5f) << "the full size would take 200 ms";
  // 120 ms at full size: 5/8 would fit 50 ms (47 ms), not 40.
  EXPECT_EQ(moveFor(12, 0.006), 0.5f) << "no step up without room to spare";
  // 80 ms: 5/8 takes 31 ms.
  EXPECT_EQ(moveFor(12, 0.004), 0.625f);
  EXPECT_EQ(moveFor(12, 0.02), 0.25f) << "down at once";
}

// The sessions whose frames answer input take turns on one device: each holds target_fps with
// its share of the frame time. A session whose frames refine a resting view takes no share (the
// render loop serves it once no session is interactive), nor does one whose client went quiet
// with a change still to show (it stopped acking).
TEST(SessionState, InteractiveSessionsShareTheFrameBudget) {
  SessionDefaults d = defaults(RenderMode::PostProcess);
  d.targetFps = 20.0;  // 50 ms a frame
  SessionState s(d, {200, 100});
  SessionState other(d, {200, 100});
  EXPECT_TRUE(other.interactive(kStart)) << "a new session's first frame";
  sentAndAcked(other, other.startFrame(kStart, noFocus).frame, kStart);
  ASSERT_TRUE(other.nextFrameDue()) << "its raster refines the still view";
  EXPECT_FALSE(other.interactive(kStart)) << "refining frames answer no input";
  uint32_t frame = 0;
  // A moving frame planned while `sharers` sessions are interactive; every pixel takes 0.004 ms
  // (80 ms at full size).
  auto scaleSharing = [&](uint32_t sharers) {
    auto at = kStart + std::chrono::milliseconds(10 * ++frame);
    s.apply(camera(frame, float(frame)), at);
    EXPECT_TRUE(s.interactive(at));
    s.shareDevice(sharers);
    return frameTaking(s, frame, at, 0.004).renderScale;
  };
  EXPECT_EQ(scaleSharing(1), 1.0f) << "the first frame: no time known yet";
  EXPECT_EQ(scaleSharing(1), 0.75f) << "50 ms: 45 ms at 3/4";
  EXPECT_EQ(scaleSharing(2), 0.5f) << "25 ms: 20 ms at 1/2";
  EXPECT_EQ(scaleSharing(4), 0.375f) << "12.5 ms: 11.25 ms at 3/8";
  EXPECT_EQ(scaleSharing(8), 0.25f) << "6.25 ms: never below a quarter";
  EXPECT_EQ(scaleSharing(0), 0.625f) << "alone again (no count below one): 31 ms at 5/8";

  // The view rests: after still_after_ms, the still frame at rest still answers the move.
  auto rested = kStart + 1s;
  EXPECT_TRUE(s.interactive(rested));
  ASSERT_TRUE(dueAt(s, rested));
  sentAndAcked(s, s.startFrame(rested, noFocus).frame, rested);
  EXPECT_FALSE(s.interactive(rested));

  // A change whose frames the client never acks (two in flight) stops counting after a while.
  auto change = rested + 10ms;
  s.apply(camera(++frame, 5.0f), change);
  s.startFrame(change, noFocus);
  s.apply(camera(++frame, 6.0f), change + 10ms);
  s.startFrame(change + 10ms, noFocus);
  s.apply(camera(++frame, 7.0f), change + 20ms);
  EXPECT_FALSE(s.nextFrameDue()) << "two frames unacked";
  EXPECT_TRUE(s.interactive(change + 500ms));
  EXPECT_FALSE(s.interactive(change + 1500ms));
}

// A change of the lens alone (a focus pull) keeps the size of the frame before, where the raster
// stands and only the DoF steps run: it scales down only when its own frames overrun target_fps by
// half (a new size draws the raster again), the frames that drew it not counted; the camera's
// moving frames' cost does not decide it. The same camera sent again beside the lens is no move.
TEST(SessionState, ALensChangeKeepsTheSizeItsRasterStandsAt) {
  SessionDefaults d = defaults(RenderMode::PostProcess);
  d.targetFps = 20.0;  // 50 ms a frame
  SessionState s(d, {200, 100});
  s.apply(camera(1, 0.0f), kStart);
  s.startFrame(kStart, noFocus);
  s.frameRendered(200.0);  // 0.01 ms a pixel, the G-buffer included
  sentAndAcked(s, 1, kStart);
  uint32_t frame = 1;
  const auto rested = kStart + 200ms;
  auto lensFrame = [&](float focus, double msPerPixel, bool rasterDrawn = false) {
    auto at = rested + std::chrono::milliseconds(10 * ++frame);
    s.apply(camera(frame, 0.0f), at);
    LensMessage lens;
    lens.seq = frame;
    lens.focusDistance = focus;
    s.apply(lens, at);
    FramePlan plan = frameTaking(s, frame, at, msPerPixel, rasterDrawn);
    EXPECT_TRUE(plan.moving && plan.lensOnly);
    return plan.renderScale;
  };
  // Lens frames average 0.7 of the average before and 0.3 of the new frame's ms a pixel.
  EXPECT_EQ(lensFrame(3.0f, 0.001), 1.0f) << "the size the raster stands at";
  EXPECT_EQ(lensFrame(3.5f, 0.0045), 1.0f) << "20 ms fits 50";
  EXPECT_EQ(lensFrame(4.0f, 0.0045), 1.0f) << "41 ms fits";
  EXPECT_EQ(lensFrame(4.5f, 0.02), 1.0f) << "56 ms: over by less than half";
  EXPECT_EQ(lensFrame(5.0f, 0.002), 0.5f) << "159 ms: down to what fits 50 ms";
  // The first frame at half size draws the raster there: 500 ms for its 5000 pixels.
  EXPECT_EQ(lensFrame(5.5f, 0.1, true), 0.5f);
  EXPECT_EQ(lensFrame(6.0f, 0.002), 0.5f) << "the frame that drew the raster is not counted";

  // A longer focal length frames another view, as the camera's moves do: the moving frames' scale
  // (by the first frame's cost, 200 ms at full size).
  auto at = rested + std::chrono::milliseconds(10 * ++frame);
  LensMessage zoom;
  zoom.seq = frame;
  zoom.focalLengthMm = 85.0f;
  s.apply(zoom, at);
  FramePlan zoomed = s.startFrame(at, noFocus);
  EXPECT_FALSE(zoomed.lensOnly);
  EXPECT_EQ(zoomed.renderScale, 0.5f);
}

// The first lens-only frame, before any has been timed, is scaled by a still frame that reused
// the raster (one that drew it says nothing of a lens change's cost).
TEST(SessionState, TheFirstLensChangeIsScaledByARestingFrame) {
  SessionDefaults d = defaults(RenderMode::Hybrid);
  d.targetFps = 20.0;  // 50 ms a frame
  for (bool drewRaster : {true, false}) {
    SessionState s(d, {200, 100});
    frameTaking(s, 1, kStart, 0.02, drewRaster);  // 400 ms at full size
    LensMessage lens;
    lens.seq = 2;
    lens.focusDistance = 3.0f;
    s.apply(lens, kStart + 10ms);
    FramePlan pulled = s.startFrame(kStart + 10ms, noFocus);
    ASSERT_TRUE(pulled.lensOnly);
    EXPECT_EQ(pulled.renderScale, drewRaster ? 1.0f : 0.25f) << drewRaster;
  }
}

// An input that changes nothing (the same camera, lens or mode again) gets a frame that carries
// its seq, at still quality, and the view's accumulation goes on instead of starting over (the
// frame refines: it waits while another session moves); a real change starts it over.
TEST(SessionState, AnInputThatChangesNothingGoesOnWithTheAccumulation) {
  SessionDefaults d = defaults(RenderMode::RayTrace);
  d.accumulationFrames = 100;
  SessionState s(d, {64, 48});
  s.apply(camera(1, 0.0f), kStart);
  Clock::time_point t = kStart + 1s;  // at rest
  for (uint32_t frame = 1; frame <= 3; ++frame, t += 10ms)
    sentAndAcked(s, s.startFrame(t, noFocus).frame, t);
  auto answered = [&](const ClientMessage& message, uint32_t seq) {
    t += 10ms;
    EXPECT_FALSE(s.apply(message, t));
    EXPECT_TRUE(dueAt(s, t));
    EXPECT_EQ(s.interactive(t), seq == 5u) << "only a change is new input";
    FramePlan plan = s.startFrame(t, noFocus);
    sentAndAcked(s, plan.frame, t);
    EXPECT_EQ(plan.seq, seq);
    return plan;
  };
  FramePlan same = answered(camera(2, 0.0f), 2);
  EXPECT_EQ(same.accumulatedFrames, 4u) << "the same camera: the accumulation goes on";
  EXPECT_FALSE(same.moving);
  EXPECT_EQ(same.jpegQuality, 90);
  LensMessage lens;
  lens.seq = 3;
  const Lens& current = s.lens();
  lens.focalLengthMm = current.focalLengthMm;
  lens.fNumber = current.fNumber;
  lens.focusDistance = current.focusDistance;
  lens.blades = current.blades;
  lens.sensor = current.sensor;
  EXPECT_EQ(answered(lens, 3).accumulatedFrames, 5u) << "the same lens";
  EXPECT_EQ(answered(ModeMessage{4, RenderMode::RayTrace, DebugView::Final}, 4).accumulatedFrames,
            6u)
      << "the same mode";
  FramePlan moved = answered(camera(5, 1.0f), 5);
  EXPECT_EQ(moved.accumulatedFrames, 1u) << "a new camera starts over";
  EXPECT_TRUE(moved.moving);
}

TEST(SessionState, TargetFpsZeroNeverScales) {
  SessionDefaults d = defaults(RenderMode::PostProcess);
  d.targetFps = 0.0;
  SessionState s(d, {200, 100});
  s.apply(camera(1, 0.0f), kStart);
  s.startFrame(kStart, noFocus);
  s.frameRendered(10000.0);
  sentAndAcked(s, 1, kStart);
  s.apply(camera(2, 1.0f), kStart + 10ms);
  EXPECT_EQ(s.startFrame(kStart + 10ms, noFocus).request.settings.width, 200u);
}

TEST(SessionState, ResolutionScaleAndModeChange) {
  SessionState s(defaults(RenderMode::PostProcess), {200, 100});
  SettingsMessage settings;
  settings.resolutionScale = 0.5f;
  s.apply(settings, kStart);
  EXPECT_EQ(s.renderSize().width, 100u);
  EXPECT_EQ(s.renderSize().height, 50u);
  s.apply(ModeMessage{4, RenderMode::Hybrid, DebugView::Mask}, kStart);
  FramePlan plan = s.startFrame(kStart, noFocus);
  EXPECT_TRUE(plan.resetHistory);
  EXPECT_EQ(plan.request.mode, RenderMode::Hybrid);
  EXPECT_EQ(plan.request.view, DebugView::Mask);
  EXPECT_EQ(plan.request.settings.width, 100u);
  EXPECT_EQ(plan.seq, 4u);
}

}  // namespace
}  // namespace hdof::net
