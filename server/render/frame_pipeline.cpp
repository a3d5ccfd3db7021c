#include "render/frame_pipeline.h"

#include <algorithm>
#include <chrono>
#include <cstring>

namespace hdof {
namespace {

bool sameView(const Camera& a, const Camera& b) {
  return a.position == b.position && a.forward == b.forward && a.up == b.up && a.yfov == b.yfov;
}

bool sameLens(const Lens& a, const Lens& b) {
  return a.focalLengthMm == b.focalLengthMm && a.fNumber == b.fNumber &&
         a.focusDistance == b.focusDistance && a.blades == b.blades &&
         a.bladeRotation == b.bladeRotation;
}

void computeToCompute(VkCommandBuffer cmd) {
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
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
      targets_(std::make_unique<RenderTargets>(context, width, height)),
      gbuffer_(context, scene, gpuScene),
      postProcess_(context, width, height),
      hybrid_(context, gpuScene, width, height),
      reference_(context, gpuScene),
      tonemap_(context),
      frameUniforms_(context, sizeof(gpu::FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                     gpu::MemoryUse::Upload, "frame uniforms"),
      timer_(context),
      commandBuffer_(context.allocateCommandBuffer()),
      fence_(gpu::createFence(context)) {
  gbuffer_.bindTargets(*targets_);
}

FramePipeline::~FramePipeline() { vkDeviceWaitIdle(context_.device()); }

void FramePipeline::resize(uint32_t width, uint32_t height) {
  if (width == targets_->width && height == targets_->height) return;
  VK_CHECK(vkQueueWaitIdle(context_.queue()));
  targets_.reset();
  targets_ = std::make_unique<RenderTargets>(context_, width, height);
  gbuffer_.bindTargets(*targets_);
  postProcess_.resize(width, height);
  hybrid_.resize(width, height);
  accumulation_.valid = false;
  readback_ = gpu::Buffer();
  previousViewProj_.reset();
}

FrameStats FramePipeline::render(const FrameRequest& request) {
  if (request.settings.width != targets_->width || request.settings.height != targets_->height)
    throw std::logic_error("FramePipeline::render: request size differs from the targets");
  gpu::FrameUniforms uniforms =
      makeFrameUniforms(scene_, request.camera, request.lens, request.settings);
  uniforms.previousViewProj = previousViewProj_.value_or(uniforms.viewProj);
  previousViewProj_ = uniforms.viewProj;
  std::memcpy(frameUniforms_.mapped(), &uniforms, sizeof(uniforms));

  VkCommandBuffer cmd = commandBuffer_;
  VK_CHECK(vkResetCommandBuffer(cmd, 0));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
  timer_.reset(cmd);
  // The previous frame's writes (same targets) are done and visible before this one starts.
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT,
                     VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                     VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT);

  const gpu::Image* radiance = &targets_->color;
  switch (request.mode) {
    case RenderMode::Pinhole:
    case RenderMode::PostProcess:
    case RenderMode::Hybrid:
      timer_.begin(cmd, "visibility");
      gbuffer_.recordVisibility(cmd, frameUniforms_, *targets_);
      timer_.end(cmd);
      timer_.begin(cmd, "gbuffer");
      gbuffer_.recordResolve(cmd, frameUniforms_, *targets_);
      timer_.end(cmd);
      if (request.mode != RenderMode::Pinhole) {
        postProcess_.record(cmd, timer_, frameUniforms_, *targets_);
        radiance = &postProcess_.output();
      }
      if (request.mode == RenderMode::Hybrid) {
        hybrid_.record(cmd, timer_, frameUniforms_, *targets_, postProcess_.output(), request.view,
                       request.traceEverywhere);
        radiance = &hybrid_.output();
      }
      break;
    case RenderMode::RayTrace:
    case RenderMode::Reference: {
      uint32_t firstSample = request.firstSample;
      bool accumulate = request.accumulate;
      if (request.mode == RenderMode::RayTrace) {
        bool keep = accumulation_.valid && accumulation_.mode == RenderMode::RayTrace &&
                    accumulation_.raysPerFrame == request.settings.samplesPerPixel &&
                    sameView(accumulation_.camera, request.camera) &&
                    sameLens(accumulation_.lens, request.lens);
        firstSample = keep ? accumulation_.samples : 0;
        accumulate = keep;
      }
      timer_.begin(cmd, modeName(request.mode));
      uint32_t sequence = request.mode == RenderMode::Reference ? 0 : 1;
      reference_.record(cmd, frameUniforms_, *targets_,
                        {firstSample, request.settings.samplesPerPixel, accumulate, sequence});
      timer_.end(cmd);
      computeToCompute(cmd);
      radiance = &targets_->accumulation;
      accumulation_ = {true,
                       request.mode,
                       request.camera,
                       request.lens,
                       request.settings.samplesPerPixel,
                       (accumulate ? accumulation_.samples : 0) + request.settings.samplesPerPixel};
      break;
    }
  }
  timer_.begin(cmd, "tonemap");
  tonemap_.record(cmd, frameUniforms_, *radiance, *targets_);
  timer_.end(cmd);
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
  for (const auto& [name, ms] : stats.passMs) stats.gpuMs += ms;
  if (request.mode == RenderMode::RayTrace || request.mode == RenderMode::Reference) {
    stats.accumulatedSamples = accumulation_.samples;
    stats.raysShot = uint64_t(width()) * height() * request.settings.samplesPerPixel;
  }
  if (request.mode == RenderMode::Hybrid) {
    stats.maskCoverage = hybrid_.maskCoverage();
    stats.raysShot = hybrid_.raysShot();
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

const void* FramePipeline::readTarget(const gpu::Image& image, uint32_t bytesPerPixel) {
  VkDeviceSize bytes = VkDeviceSize(targets_->width) * targets_->height * bytesPerPixel;
  if (readback_.size() < bytes)
    readback_ = gpu::Buffer(context_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                            gpu::MemoryUse::Readback, "target readback");
  context_.submitAndWait(
      [&](VkCommandBuffer cmd) { gpu::copyImageToBuffer(cmd, image, readback_); });
  return readback_.mapped();
}

std::vector<float> FramePipeline::linearDepth() {
  const auto* texels = static_cast<const glm::vec4*>(readTarget(targets_->normalDepth, 16));
  std::vector<float> depth(size_t(targets_->width) * targets_->height);
  for (size_t i = 0; i < depth.size(); ++i) depth[i] = texels[i].w;
  return depth;
}

std::vector<glm::vec2> FramePipeline::motionVectors() {
  const auto* texels = static_cast<const uint32_t*>(readTarget(targets_->motion, 4));
  std::vector<glm::vec2> motion(size_t(targets_->width) * targets_->height);
  for (size_t i = 0; i < motion.size(); ++i) motion[i] = glm::unpackHalf2x16(texels[i]);
  return motion;
}

ImageRgba8 FramePipeline::image() const {
  ImageRgba8 image;
  image.width = targets_->width;
  image.height = targets_->height;
  image.pixels.resize(size_t(image.width) * image.height * 4);
  std::memcpy(image.pixels.data(), targets_->readback.mapped(), image.pixels.size());
  return image;
}

}  // namespace hdof
