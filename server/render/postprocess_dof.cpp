#include "render/postprocess_dof.h"

#include <shared/dof.h>

#include <stdexcept>

namespace hdof {

struct PostProcessDof::Images {
  Images(const gpu::Context& context, uint32_t width, uint32_t height);

  uint32_t width, height;
  gpu::Image coc;                        // r16f, full resolution
  gpu::Image tiles, dilatedTiles;        // rg16f, one texel per tile: largest |CoC|, nearest CoC
  gpu::Image halfColorCoc, prefiltered;  // rgba16f, half resolution, alpha = CoC
  gpu::Image farLayer, nearLayer;        // rgba16f, half resolution: the gather's
  gpu::Image farFiltered, nearFiltered;  // the same after the median
  gpu::Image output;                     // rgba16f, full resolution
};

namespace {

gpu::Image makeImage(const gpu::Context& context, uint32_t width, uint32_t height, VkFormat format,
                     const char* name) {
  // Sampled too, so the tonemap and debug views can read any of them.
  return gpu::createImage2D(context, width, height, format,
                            VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, name);
}

uint32_t divideRoundingUp(uint32_t value, uint32_t divisor) {
  return (value + divisor - 1) / divisor;
}

void computeToCompute(VkCommandBuffer cmd) {
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

}  // namespace

PostProcessDof::Images::Images(const gpu::Context& context, uint32_t w, uint32_t h)
    : width(w), height(h) {
  constexpr VkFormat kColor = VK_FORMAT_R16G16B16A16_SFLOAT;
  constexpr VkFormat kTile = VK_FORMAT_R16G16_SFLOAT;
  uint32_t halfW = divideRoundingUp(w, 2), halfH = divideRoundingUp(h, 2);
  uint32_t tilesW = divideRoundingUp(w, gpu::kDofTileSize);
  uint32_t tilesH = divideRoundingUp(h, gpu::kDofTileSize);
  coc = makeImage(context, w, h, VK_FORMAT_R16_SFLOAT, "dof coc");
  tiles = makeImage(context, tilesW, tilesH, kTile, "dof tiles");
  dilatedTiles = makeImage(context, tilesW, tilesH, kTile, "dof dilated tiles");
  halfColorCoc = makeImage(context, halfW, halfH, kColor, "dof half colour");
  prefiltered = makeImage(context, halfW, halfH, kColor, "dof prefiltered");
  farLayer = makeImage(context, halfW, halfH, kColor, "dof far layer");
  nearLayer = makeImage(context, halfW, halfH, kColor, "dof near layer");
  farFiltered = makeImage(context, halfW, halfH, kColor, "dof far filtered");
  nearFiltered = makeImage(context, halfW, halfH, kColor, "dof near filtered");
  output = makeImage(context, w, h, kColor, "dof output");
  gpu::makeGeneral(context, {&coc, &tiles, &dilatedTiles, &halfColorCoc, &prefiltered, &farLayer,
                             &nearLayer, &farFiltered, &nearFiltered, &output});
}

PostProcessDof::PostProcessDof(const gpu::Context& context, uint32_t width, uint32_t height)
    : context_(context),
      images_(std::make_unique<Images>(context, width, height)),
      downsample_(context),
      tiles_(context),
      dilate_(context),
      prefilter_(context),
      gather_(context),
      median_(context),
      composite_(context) {}

PostProcessDof::~PostProcessDof() = default;

void PostProcessDof::resize(uint32_t width, uint32_t height) {
  if (width == images_->width && height == images_->height) return;
  VK_CHECK(vkQueueWaitIdle(context_.queue()));
  images_.reset();
  images_ = std::make_unique<Images>(context_, width, height);
}

void PostProcessDof::record(VkCommandBuffer cmd, gpu::GpuTimer& timer,
                            const gpu::Buffer& frameUniforms, const RenderTargets& targets) const {
  const Images& im = *images_;
  if (targets.width != im.width || targets.height != im.height)
    throw std::logic_error("PostProcessDof::record: targets size differs from the images");
  // Each pass reads what the one before wrote (the first, the G-buffer's compute resolve).
  auto timed = [&](const char* name, auto&& recordPass) {
    computeToCompute(cmd);
    timer.begin(cmd, name);
    recordPass();
    timer.end(cmd);
  };
  timed("dof_downsample", [&] {
    downsample_.record(cmd, frameUniforms, targets.color, targets.normalDepth, im.coc,
                       im.halfColorCoc);
  });
  timed("dof_tiles", [&] { tiles_.record(cmd, frameUniforms, im.coc, im.tiles); });
  timed("dof_dilate", [&] { dilate_.record(cmd, frameUniforms, im.tiles, im.dilatedTiles); });
  timed("dof_prefilter", [&] {
    prefilter_.record(cmd, frameUniforms, im.halfColorCoc, im.dilatedTiles, im.prefiltered);
  });
  timed("dof_gather", [&] {
    gather_.record(cmd, frameUniforms, im.prefiltered, im.dilatedTiles, im.farLayer, im.nearLayer);
  });
  timed("dof_median", [&] {
    median_.record(cmd, frameUniforms, im.farLayer, im.nearLayer, im.dilatedTiles, im.farFiltered,
                   im.nearFiltered);
  });
  timed("dof_composite", [&] {
    composite_.record(cmd, frameUniforms, targets.color, im.coc, im.farFiltered, im.nearFiltered,
                      im.dilatedTiles, im.output);
  });
  computeToCompute(cmd);
}

const gpu::Image& PostProcessDof::output() const { return images_->output; }

const gpu::Image& PostProcessDof::coc() const { return images_->coc; }

const gpu::Image& PostProcessDof::farLayer() const { return images_->farFiltered; }

const gpu::Image& PostProcessDof::nearLayer() const { return images_->nearFiltered; }

}  // namespace hdof
