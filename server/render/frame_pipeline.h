// One session's frame pipeline: the passes strung together for a mode (docs/design.md lists them),
// rendering into the session's images. Synchronous: render() returns when the frame is on the
// CPU.
#pragma once

#include "image/image.h"
#include "render/camera.h"
#include "render/frame_images.h"
#include "render/gbuffer_pass.h"
#include "render/hybrid_dof.h"
#include "render/modes.h"
#include "render/postprocess_dof.h"

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hdof {

struct FrameRequest {
  RenderMode mode = RenderMode::Pinhole;
  Camera camera;
  Lens lens;
  FrameSettings settings;  // settings.samplesPerPixel: rays per pixel this frame (ray tracing)
  // reference: the rays traced start at number firstSample of each pixel's sample sequence, and
  // are added to the previous frame's (accumulate) or start a new sum. raytrace ignores both: it
  // accumulates while the camera and lens stay the same and starts over when they change.
  uint32_t firstSample = 0;
  bool accumulate = false;
  DebugView view = DebugView::Final;  // hybrid: what the frame shows
  // hybrid: trace every pixel at the full rays, as if the mask covered the image (measures the
  // reconstruction and composite against raytrace).
  bool traceEverywhere = false;
  // Timestamps around each step (FrameStats::passMs and gpuMs; empty and 0 without). They cost a
  // software device a few percent of a frame, which an untimed frame saves.
  bool timePasses = true;
};

struct FrameStats {
  std::vector<std::pair<std::string, double>> passMs;  // GPU time per pass, when timed
  double gpuMs = 0.0;                                  // sum of the passes
  double wallMs = 0.0;                                 // submit to finish, as the CPU saw it
  uint32_t accumulatedSamples = 0;  // ray-traced modes: rays per pixel in the image so far
  double maskCoverage = 0.0;        // hybrid: the fraction of pixels the ray mask traced
  uint64_t raysShot = 0;            // ray-traced modes: camera rays traced this frame
  bool rasterDrawn = false;         // the G-buffer was drawn (a new view, size or raster sample)
  double passMsOf(const std::string& pass) const;
};

class FramePipeline {
 public:
  FramePipeline(const gpu::Context& context, const Scene& scene, const GpuScene& gpuScene,
                uint32_t width, uint32_t height);
  ~FramePipeline();
  FramePipeline(const FramePipeline&) = delete;
  FramePipeline& operator=(const FramePipeline&) = delete;

  // Renders one frame (request.settings' size must match the images; see resize()).
  FrameStats render(const FrameRequest& request);
  // Renders `reference` with raysPerPixel rays per pixel in submissions of about a million rays
  // (short enough for any driver's watchdog); onProgress(rays per pixel done) after each.
  FrameStats renderReference(FrameRequest request, uint32_t raysPerPixel,
                             const std::function<void(uint32_t)>& onProgress = {});
  // Remakes the images for a new viewport (waits for the GPU first); the history starts over.
  void resize(uint32_t width, uint32_t height);
  // Forgets the temporal history: the next frame starts every accumulation over (the raster's
  // anti-aliasing, hybrid and raytrace).
  void resetHistory() {
    accumulation_.valid = false;
    raster_.valid = false;
    hybrid_.resetHistory();
  }
  uint32_t width() const { return images_->width; }
  uint32_t height() const { return images_->height; }
  // The images of the last frame (for tests and debugging).
  const FrameImages& images() const { return *images_; }
  // The hybrid's temporal history as the last frame left it.
  const HybridImages::History& hybridHistory() const {
    return images_->hybrid.history[hybrid_.current()];
  }
  // The last rendered frame, tonemapped.
  ImageRgba8 image() const;
  // Linear view depth (metres, kBackgroundDepth where nothing is) of the last frame that ran
  // the G-buffer, row-major.
  std::vector<float> linearDepth();
  // Motion vectors of the last frame that ran the G-buffer (see GBufferImages::motion).
  std::vector<glm::vec2> motionVectors();
  // Forgets the previous frame's view: the next frame's motion is zero (a camera cut).
  void cut() {
    previousViewProj_.reset();
    raster_.valid = false;
  }

 private:
  const gpu::Context& context_;
  const Scene& scene_;
  const GpuScene& gpuScene_;
  std::unique_ptr<FrameImages> images_;
  GBufferPass gbuffer_;
  PostProcessDof postProcess_;
  HybridDof hybrid_;
  gpu::ComputeProgram rayTrace_;  // reference and raytrace
  gpu::ComputeProgram tonemap_;
  gpu::Buffer frameUniforms_;
  gpu::GpuTimer timer_;
  VkCommandBuffer commandBuffer_ = VK_NULL_HANDLE;
  gpu::Fence fence_;
  gpu::Buffer readback_;  // for linearDepth() and motionVectors()
  std::optional<glm::mat4> previousViewProj_;

  // Records request's frame; changes no state, so that recording every mode once at start-up
  // checks every step's bindings against its shader.
  void record(VkCommandBuffer cmd, const FrameRequest& request, const gpu::FrameUniforms& uniforms,
              const gpu::RayTraceRays& rays);
  // The bytes of an image (tightly packed rows), after the GPU is idle.
  const void* readImage(const gpu::Image& image, uint32_t bytesPerPixel);

  // What the raster's anti-aliased colour holds: samples of one view (changes of the lens that
  // keep its framing, such as focus and aperture, keep it).
  struct RasterHistory {
    bool valid = false;
    Camera camera;
    Lens lens;
    uint32_t samples = 0;
    uint32_t moves = 0;        // frames in motion since the view last rested or was cut
    uint32_t stillFrames = 0;  // frames since the camera or the lens last changed
  } raster_;

  // What an output of the G-buffer as it is, through this lens, holds. A still view whose raster
  // has all its samples keeps it until the lens changes: the post-process output, its tiles, and
  // the ray mask's edges and their spread (hybrid only). The last two read depth and normals
  // alone, which a still view's further samples leave as they are (they add colour): made from
  // one of those frames (stillRaster; for the edges, one whose lens rested too), they stand over
  // the later ones too.
  struct LensOutput {
    bool valid = false;
    Lens lens;
    bool stillRaster = false;
  };
  LensOutput dofOutput_, dofTiles_, maskEdges_;
  // This frame reuses images.dof.output, or only the post-process's tiles and their lists
  // (record() reads them).
  bool keepDofOutput_ = false, keepDofTiles_ = false;

  // What the ray-traced accumulation holds, so raytrace knows when to start over.
  struct Accumulation {
    bool valid = false;
    RenderMode mode = RenderMode::Pinhole;
    Camera camera;
    Lens lens;
    uint32_t raysPerFrame = 0;
    uint32_t samples = 0;
  } accumulation_;
};

// Renders a few frames of every streamed mode at a small size (a cut, a move, a still view's
// frames to past its raster's last sample, a focus pull), so that each pipeline a session runs has
// run once. The pipelines are the process's (gpu::Context::shared): on a driver that compiles a
// pipeline at its first use (lavapipe), no session's frame then waits for the compiler.
void warmUpPipelines(const gpu::Context& context, const Scene& scene, const GpuScene& gpuScene);

// Makes this process keep the memory it frees for its next frames (call once, before rendering).
// Every frame the Vulkan driver allocates and frees about the same memory (lavapipe bins the
// G-buffer draw's triangles in 64 kB blocks, 10-25 MB a frame). By default glibc gives a freed heap
// top over 128 kB back to the kernel and maps each block over 128 kB afresh, so the next frame
// faults those pages in again: with lavapipe, one hybrid frame in three to five at 254x175 took
// 120-160 ms instead of 30-40. Kept: up to 1 GB free at a heap's top, and blocks up to 32 MB (the
// most glibc allows) come from the heap.
void keepFreedMemoryForFrames();

}  // namespace hdof
