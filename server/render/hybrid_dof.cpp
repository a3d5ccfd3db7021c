#include "render/hybrid_dof.h"

namespace hdof {
namespace {

std::unique_ptr<gpu::Image> makeOutput(const gpu::Context& context, uint32_t w, uint32_t h) {
  return gpu::createGeneralImage2D(context, w, h, VK_FORMAT_R16G16B16A16_SFLOAT,
                                   VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                   "hybrid output");
}

void computeToCompute(VkCommandBuffer cmd) {
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

}  // namespace

HybridDof::HybridDof(const gpu::Context& context, const GpuScene& scene, uint32_t width,
                     uint32_t height)
    : context_(context),
      mask_(context, width, height),
      layers_(std::make_unique<HybridTraceLayers>(context, width, height)),
      trace_(context, scene),
      temporal_(context, width, height),
      spatial_(context, width, height),
      composite_(context),
      debugView_(context),
      output_(makeOutput(context, width, height)) {}

HybridDof::~HybridDof() = default;

void HybridDof::resize(uint32_t width, uint32_t height) {
  if (width == output_->width() && height == output_->height()) return;
  VK_CHECK(vkQueueWaitIdle(context_.queue()));
  mask_.resize(width, height);
  layers_ = std::make_unique<HybridTraceLayers>(context_, width, height);
  temporal_.resize(width, height);
  spatial_.resize(width, height);
  output_ = makeOutput(context_, width, height);
  hasHistory_ = false;
}

void HybridDof::record(VkCommandBuffer cmd, gpu::GpuTimer& timer, const gpu::Buffer& frameUniforms,
                       const RenderTargets& targets, const gpu::Image& postProcess, DebugView view,
                       bool traceEverywhere) {
  computeToCompute(cmd);
  mask_.record(cmd, timer, frameUniforms, targets, hasHistory_ ? &temporal_.variance() : nullptr,
               traceEverywhere);
  timer.begin(cmd, "hybrid_trace");
  trace_.record(cmd, frameUniforms, mask_.workList(), *layers_);
  timer.end(cmd);
  computeToCompute(cmd);
  timer.begin(cmd, "hybrid_temporal");
  temporal_.record(cmd, frameUniforms, mask_.rays(), mask_.workList(), *layers_, targets,
                   !hasHistory_);
  timer.end(cmd);
  computeToCompute(cmd);
  timer.begin(cmd, "hybrid_spatial");
  spatial_.record(cmd, frameUniforms, mask_.workList(), mask_.rays(), *layers_, temporal_);
  timer.end(cmd);
  computeToCompute(cmd);
  timer.begin(cmd, "hybrid_composite");
  const gpu::Image& nearLayer = spatial_.nearLayer();
  const gpu::Image& farLayer = spatial_.farLayer();
  if (view == DebugView::Final)
    composite_.record(cmd, frameUniforms, mask_.rays(), targets, postProcess, nearLayer, farLayer,
                      *output_);
  else
    debugView_.record(cmd, frameUniforms, view, mask_.rays(), targets, nearLayer, farLayer,
                      *output_);
  timer.end(cmd);
  computeToCompute(cmd);
  hasHistory_ = true;
}

}  // namespace hdof
