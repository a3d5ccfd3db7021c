#include "render/frame_pipeline.h"

#include <malloc.h>
#include <algorithm>
#include <chrono>
#include <cstring>

namespace hdof {
namespace {

constexpr VkCommandBufferBeginInfo kOneTimeSubmit{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                                  nullptr,
                                                  VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};

// Point i of the Halton sequence in base b, in [0, 1).
float halton(uint32_t i, uint32_t base) {
  float scale = 1.0f, result = 0.0f;
  for (; i > 0; i /= base) {
    scale /= float(base);
    result += scale * float(i % base);
  }
  return result;
}

// The raster's jitter for the n-th frame of a still view (or of a move), from the pixel centre:
// none first, then the (2, 3) Halton points, kJitterCycle in all.
constexpr uint32_t kJitterCycle = 16;
glm::vec2 rasterJitter(uint32_t frame) {
  uint32_t i = frame % kJitterCycle;
  return i == 0 ? glm::vec2(0.0f) : glm::vec2(halton(i, 2), halton(i, 3)) - 0.5f;
}

// The framing: where the camera is and what it sees, which focal length and sensor decide.
bool sameView(const Camera& a, const Lens& aLens, const Camera& b, const Lens& bLens) {
  return a.position == b.position && a.forward == b.forward && a.up == b.up &&
         aLens.focalLengthMm == bLens.focalLengthMm && aLens.sensor == bLens.sensor;
}

}  // namespace

double FrameStats::passMsOf(const std::string& pass) const {
  for (const auto& [name, ms] : passMs)
    if (name == pass) return ms;
  return 0.0;
}

FramePipeline::FramePipeline(const gpu::Context& context, const Scene& scene,
                             const GpuScene& gpuScene, uint32_t width, uint32_t height)
    : context_(context),
      scene_(scene),
      gpuScene_(gpuScene),
      images_(std::make_unique<FrameImages>(context, width, height)),
      gbuffer_(context, scene, gpuScene),
      postProcess_(context),
      hybrid_(context, gpuScene),
      rayTrace_(context, "reference.comp", &gpuScene.setLayout()),
      tonemap_(context, "tonemap.comp"),
      frameUniforms_(context, sizeof(gpu::FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                     gpu::MemoryUse::Upload, "frame uniforms"),
      timer_(context),
      commandBuffer_(context.allocateCommandBuffer()),
      fence_(gpu::createFence(context)) {
  gbuffer_.bindImages(images_->gbuffer, width, height);
  // Every mode and the debug views recorded once, not submitted: a binding that does not match its
  // shader is an error now rather than on a client's first frame in that mode.
  VK_CHECK(vkBeginCommandBuffer(commandBuffer_, &kOneTimeSubmit));
  FrameRequest request;
  request.settings.width = width;
  request.settings.height = height;
  gpu::FrameUniforms uniforms =
      makeFrameUniforms(scene, request.camera, request.lens, request.settings);
  for (RenderMode mode :
       {RenderMode::Pinhole, RenderMode::PostProcess, RenderMode::Hybrid, RenderMode::RayTrace}) {
    request.mode = mode;
    timer_.reset(commandBuffer_);
    record(commandBuffer_, request, uniforms, {});
  }
  request.mode = RenderMode::Hybrid;
  // The debug views share one shader, except the in-focus zone's, drawn over the composite.
  for (DebugView view : {DebugView::Mask, DebugView::FocusZone}) {
    request.view = view;
    timer_.reset(commandBuffer_);
    record(commandBuffer_, request, uniforms, {});
  }
  VK_CHECK(vkEndCommandBuffer(commandBuffer_));
  VK_CHECK(vkResetCommandBuffer(commandBuffer_, 0));
}

FramePipeline::~FramePipeline() { vkDeviceWaitIdle(context_.device()); }

void FramePipeline::resize(uint32_t width, uint32_t height) {
  if (width == images_->width && height == images_->height) return;
  VK_CHECK(vkQueueWaitIdle(context_.queue()));
  images_.reset();
  images_ = std::make_unique<FrameImages>(context_, width, height);
  gbuffer_.bindImages(images_->gbuffer, width, height);
  // The new images hold nothing yet: the raster starts over from a first frame.
  raster_.valid = false;
  hybrid_.resetHistory();
  accumulation_.valid = false;
  dofOutput_.valid = false;
  dofTiles_.valid = false;
  maskEdges_.valid = false;
  readback_ = gpu::Buffer();
  previousViewProj_.reset();
}

void FramePipeline::record(VkCommandBuffer cmd, const FrameRequest& request,
                           const gpu::FrameUniforms& uniforms, const gpu::RayTraceRays& rays) {
  StepRecorder steps(cmd, timer_, frameUniforms_, gpuScene_);
  const FrameImages& im = *images_;
  const gpu::Image* radiance = &im.accumulation;
  switch (request.mode) {
    case RenderMode::Pinhole:
    case RenderMode::PostProcess:
    case RenderMode::Hybrid:
      // A still view whose raster has all its samples keeps its G-buffer.
      if (uniforms.rasterSample < gpu::kStillRasterFrames)
        gbuffer_.record(steps, im.gbuffer, uniforms, raster_.valid);
      radiance = &im.gbuffer.color;
      if (request.mode != RenderMode::Pinhole) {
        if (!keepDofOutput_)
          postProcess_.record(steps, im.gbuffer, im.dof, keepDofTiles_,
                              uniforms.bladeCount >= 3.0f);
        radiance = &im.dof.output;
      }
      if (request.mode == RenderMode::Hybrid) {
        hybrid_.record(steps, im);
        radiance = &im.hybrid.output;
      }
      break;
    case RenderMode::RayTrace:
    case RenderMode::Reference:
      steps.dispatch(rayTrace_, {{"accumulation", im.accumulation}},
                     gpu::Grid::over(im.accumulation), rays, modeName(request.mode));
      break;
  }
  steps.dispatch(tonemap_, {{"radiance", *radiance}, {"display", im.display}},
                 gpu::Grid::over(im.display));
  steps.step("readback",
             [&](VkCommandBuffer cmd) { gpu::copyImageToBuffer(cmd, im.display, im.readback); });
}

FrameStats FramePipeline::render(const FrameRequest& request) {
  if (request.settings.width != images_->width || request.settings.height != images_->height)
    throw std::logic_error("FramePipeline::render: request size differs from the images");
  gpu::FrameUniforms uniforms =
      makeFrameUniforms(scene_, request.camera, request.lens, request.settings);
  uniforms.previousViewProj = previousViewProj_.value_or(uniforms.viewProj);
  bool raster = request.mode == RenderMode::Pinhole || request.mode == RenderMode::PostProcess ||
                request.mode == RenderMode::Hybrid;
  bool stillRaster = raster_.valid &&
                     sameView(raster_.camera, raster_.lens, request.camera, request.lens) &&
                     request.settings.pixelJitter;
  // In motion too each frame samples another position in the pixel (after a cut, the centre),
  // which the reprojected history gathers, as TAA does.
  bool moving = raster_.valid && !stillRaster && request.settings.pixelJitter;
  uniforms.rasterSample = stillRaster ? raster_.samples : 0;
  uniforms.stillFrames =
      raster_.valid && sameView(raster_.camera, raster_.lens, request.camera, request.lens) &&
              raster_.lens == request.lens
          ? raster_.stillFrames + 1
          : 0;
  // Neither the G-buffer nor the lens changed since the post-process (its tiles, the ray mask's
  // edges) last ran: its output stands; the tiles and edges also over a still view's further
  // samples (geometryOnly, see LensOutput).
  bool drawsGBuffer = raster && uniforms.rasterSample < gpu::kStillRasterFrames;
  auto stands = [&](const LensOutput& output, bool geometryOnly) {
    bool sameRaster =
        !drawsGBuffer || (geometryOnly && output.stillRaster && uniforms.rasterSample > 0);
    return sameRaster && output.valid && output.lens == request.lens;
  };
  // The ray mask's edges take in a resting view's edges too (viewRests() in the shaders): edges
  // made for a frame whose lens changed do not stand once it rests, nor the reverse.
  bool viewRests = uniforms.rasterSample > 0 && uniforms.stillFrames > 0;
  bool needsDof = request.mode == RenderMode::PostProcess || request.mode == RenderMode::Hybrid;
  keepDofOutput_ = needsDof && stands(dofOutput_, false);
  keepDofTiles_ = needsDof && stands(dofTiles_, true);
  if (request.mode == RenderMode::Hybrid)
    hybrid_.startFrame(uniforms, stands(maskEdges_, true) && maskEdges_.stillRaster == viewRests,
                       request.view, request.traceEverywhere);
  uniforms.rasterJitter = rasterJitter(stillRaster ? raster_.samples
                                       : moving ? 1 + raster_.moves % (kJitterCycle - 1)
                                                : 0);
  std::memcpy(frameUniforms_.mapped(), &uniforms, sizeof(uniforms));

  // raytrace accumulates while the camera and lens stay the same and starts over when they
  // change; reference does as the request says.
  gpu::RayTraceRays rays{request.firstSample, request.settings.samplesPerPixel,
                         request.accumulate ? 1u : 0u, gpu::kSequenceReference};
  if (request.mode == RenderMode::RayTrace) {
    bool keep = accumulation_.valid && accumulation_.mode == RenderMode::RayTrace &&
                accumulation_.raysPerFrame == request.settings.samplesPerPixel &&
                sameView(accumulation_.camera, accumulation_.lens, request.camera, request.lens) &&
                accumulation_.lens == request.lens;
    rays = {keep ? accumulation_.samples : 0, request.settings.samplesPerPixel, keep ? 1u : 0u,
            gpu::kSequenceRayTrace};
  }

  VkCommandBuffer cmd = commandBuffer_;
  VK_CHECK(vkResetCommandBuffer(cmd, 0));
  VK_CHECK(vkBeginCommandBuffer(cmd, &kOneTimeSubmit));
  timer_.reset(cmd, request.timePasses);
  // The previous frame's writes (same images) are done and visible before this one starts.
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT,
                     VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                     VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT);
  record(cmd, request, uniforms, rays);
  VK_CHECK(vkEndCommandBuffer(cmd));

  auto start = std::chrono::steady_clock::now();
  VkFence fence = fence_;
  VK_CHECK(vkResetFences(context_.device(), 1, &fence));
  context_.submit(cmd, fence);
  VK_CHECK(vkWaitForFences(context_.device(), 1, &fence, VK_TRUE, UINT64_MAX));
  FrameStats stats;
  stats.wallMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  stats.passMs = timer_.results();
  stats.rasterDrawn = drawsGBuffer;
  for (const auto& [name, ms] : stats.passMs) stats.gpuMs += ms;

  previousViewProj_ = uniforms.viewProj;
  if (drawsGBuffer || needsDof) {
    dofOutput_ = {needsDof, request.lens};
    dofTiles_ = {needsDof, request.lens, uniforms.rasterSample > 0};
  }
  bool hybrid = request.mode == RenderMode::Hybrid;
  if (drawsGBuffer || hybrid) maskEdges_ = {hybrid, request.lens, viewRests};
  keepDofOutput_ = keepDofTiles_ = false;
  if (raster)
    raster_ = {true,
               request.camera,
               request.lens,
               uniforms.rasterSample + 1,
               moving ? raster_.moves + 1 : 0,
               uniforms.stillFrames};
  bool rayTraced = request.mode == RenderMode::RayTrace || request.mode == RenderMode::Reference;
  if (rayTraced) {
    accumulation_ = {true,
                     request.mode,
                     request.camera,
                     request.lens,
                     request.settings.samplesPerPixel,
                     (rays.accumulate ? accumulation_.samples : 0) + rays.sampleCount};
    stats.accumulatedSamples = accumulation_.samples;
    stats.raysShot = uint64_t(width()) * height() * request.settings.samplesPerPixel;
  }
  if (request.mode == RenderMode::Hybrid) {
    hybrid_.advance();
    gpu::RayWorkHeader header = readWorkHeader(images_->mask);
    stats.maskCoverage = double(header.count) / (double(width()) * height());
    stats.raysShot = header.rays;
  }
  return stats;
}

FrameStats FramePipeline::renderReference(FrameRequest request, uint32_t raysPerPixel,
                                          const std::function<void(uint32_t)>& onProgress) {
  request.mode = RenderMode::Reference;
  uint32_t base = request.firstSample;
  bool accumulate = request.accumulate;
  uint64_t pixels = uint64_t(request.settings.width) * request.settings.height;
  uint32_t batch = static_cast<uint32_t>(std::clamp<uint64_t>(1000000 / pixels, 1, 64));
  FrameStats total;
  for (uint32_t done = 0; done < raysPerPixel; done += request.settings.samplesPerPixel) {
    request.firstSample = base + done;
    request.accumulate = accumulate || done > 0;
    request.settings.samplesPerPixel = std::min(batch, raysPerPixel - done);
    FrameStats stats = render(request);
    total.gpuMs += stats.gpuMs;
    total.wallMs += stats.wallMs;
    if (onProgress) onProgress(done + request.settings.samplesPerPixel);
    total.accumulatedSamples = stats.accumulatedSamples;
  }
  return total;
}

const void* FramePipeline::readImage(const gpu::Image& image, uint32_t bytesPerPixel) {
  VkDeviceSize bytes = VkDeviceSize(image.width()) * image.height() * bytesPerPixel;
  if (readback_.size() < bytes)
    readback_ = gpu::Buffer(context_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                            gpu::MemoryUse::Readback, "target readback");
  context_.submitAndWait(
      [&](VkCommandBuffer cmd) { gpu::copyImageToBuffer(cmd, image, readback_); });
  return readback_.mapped();
}

std::vector<float> FramePipeline::linearDepth() {
  const auto* texels = static_cast<const glm::vec4*>(readImage(images_->gbuffer.normalDepth, 16));
  std::vector<float> depth(size_t(images_->width) * images_->height);
  for (size_t i = 0; i < depth.size(); ++i) depth[i] = texels[i].w;
  return depth;
}

std::vector<glm::vec2> FramePipeline::motionVectors() {
  const auto* texels = static_cast<const uint32_t*>(readImage(images_->gbuffer.motion, 4));
  std::vector<glm::vec2> motion(size_t(images_->width) * images_->height);
  for (size_t i = 0; i < motion.size(); ++i) motion[i] = glm::unpackHalf2x16(texels[i]);
  return motion;
}

ImageRgba8 FramePipeline::image() const {
  ImageRgba8 image;
  image.width = images_->width;
  image.height = images_->height;
  image.pixels.resize(size_t(image.width) * image.height * 4);
  std::memcpy(image.pixels.data(), images_->readback.mapped(), image.pixels.size());
  return image;
}

void warmUpPipelines(const gpu::Context& context, const Scene& scene, const GpuScene& gpuScene) {
  // Any size does: no frame image has a side that is a power of two, for which llvmpipe would
  // compile a shader again (gpu::ImageDesc::sidesOffPowerOfTwo).
  constexpr uint32_t kWidth = 66, kHeight = 38;
  FramePipeline pipeline(context, scene, gpuScene, kWidth, kHeight);
  FrameRequest request;
  request.settings.width = kWidth;
  request.settings.height = kHeight;
  request.lens.fNumber = 1.4f;
  request.timePasses = false;
  Camera view = scene.cameras.empty() ? Camera{} : Camera::fromScene(scene.cameras.front());
  Camera moved = view;
  moved.position -= 0.05f * view.forward;
  Lens lens = request.lens;
  for (RenderMode mode :
       {RenderMode::Hybrid, RenderMode::Pinhole, RenderMode::PostProcess, RenderMode::RayTrace}) {
    request.mode = mode;
    request.lens = lens;
    pipeline.cut();
    request.camera = moved;
    pipeline.render(request);
    request.camera = view;
    // The hybrid's frames at rest run other steps once the raster has all its samples; the
    // other modes' still frames run only steps that the hybrid's do.
    uint32_t stillFrames = mode == RenderMode::Hybrid ? gpu::kStillRasterFrames + 1 : 1;
    for (uint32_t frame = 0; frame <= stillFrames; ++frame) pipeline.render(request);
    request.lens.focusDistance *= 2.0f;
    pipeline.render(request);
  }
}

void keepFreedMemoryForFrames() {
#ifdef __GLIBC__
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
#endif
}

}  // namespace hdof
