#include "render/frame_images.h"

#include <shared/dof.h>
#include <shared/frame.h>
#include <shared/ray_work.h>

#include <cstring>

namespace hdof {
namespace {

constexpr VkFormat kColor = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kPrecise = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kPair = VK_FORMAT_R16G16_SFLOAT;
constexpr VkFormat kScalar = VK_FORMAT_R16_SFLOAT;

uint32_t divideRoundingUp(uint32_t value, uint32_t divisor) {
  return (value + divisor - 1) / divisor;
}

// A CoC tile image of a w x h viewport: one texel per kDofTileSize pixels.
gpu::Image makeTiles(gpu::ImageBatch& batch, uint32_t w, uint32_t h, VkFormat format,
                     const char* name) {
  return batch.make(divideRoundingUp(w, gpu::kDofTileSize), divideRoundingUp(h, gpu::kDofTileSize),
                    format, name);
}

}  // namespace

GBufferImages::GBufferImages(gpu::ImageBatch& batch, const gpu::Context& context, uint32_t w,
                             uint32_t h)
    : visibility(batch.make(w, h, VK_FORMAT_R32_SFLOAT, "visibility",
                            VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT)),
      rasterColor(batch.make(w, h, kColor, "raster color")),
      color(batch.make(w, h, kColor, "color")),
      colorHistory(batch.make(w, h, kColor, "color history")),
      specular(batch.make(w, h, kColor, "specular")),
      samplesAveraged(batch.make(w, h, kScalar, "samples averaged")),
      normalDepth(batch.make(w, h, kPrecise, "normal depth")),
      motion(batch.make(w, h, kPair, "motion")) {
  gpu::ImageDesc desc;
  desc.width = w;
  desc.height = h;
  desc.format = VK_FORMAT_D32_SFLOAT;
  desc.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
  desc.aspect = VK_IMAGE_ASPECT_DEPTH_BIT;
  depth = gpu::Image(context, desc, "depth");  // the render pass moves it out of UNDEFINED
  desc.samples = VkSampleCountFlagBits(gpu::kStillRasterSamples);
  multisampledDepth = gpu::Image(context, desc, "multisampled depth");
  desc.format = VK_FORMAT_R32_SFLOAT;
  desc.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
               VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  desc.aspect = VK_IMAGE_ASPECT_COLOR_BIT;
  multisampledVisibility = batch.make(desc, "multisampled visibility");
  sharedPixels = gpu::Buffer(
      context, sizeof(gpu::RayWorkHeader) + VkDeviceSize(w) * h * gpu::kRayWorkEntrySize,
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
          VK_BUFFER_USAGE_TRANSFER_DST_BIT,
      gpu::MemoryUse::DeviceOnly, "shared pixels");
}

DofImages::DofImages(gpu::ImageBatch& batch, const gpu::Context& context, uint32_t w, uint32_t h) {
  uint32_t halfW = divideRoundingUp(w, 2), halfH = divideRoundingUp(h, 2);
  colorCoc = batch.make(w, h, kColor, "dof colour coc");
  tiles = makeTiles(batch, w, h, kColor, "dof tiles");
  dilatedTiles = makeTiles(batch, w, h, kPair, "dof dilated tiles");
  halfColorCoc = batch.make(halfW, halfH, kColor, "dof half colour");
  prefiltered = batch.make(halfW, halfH, kColor, "dof prefiltered");
  farLayer = batch.make(halfW, halfH, kColor, "dof far layer");
  nearLayer = batch.make(halfW, halfH, kColor, "dof near layer");
  farFiltered = batch.make(halfW, halfH, kColor, "dof far filtered");
  nearFiltered = batch.make(halfW, halfH, kColor, "dof near filtered");
  output = batch.make(w, h, kColor, "dof output");
  tileLists = gpu::Buffer(
      context,
      sizeof(gpu::DofTileLists) +
          VkDeviceSize(gpu::kDofListCount) * tiles.width() * tiles.height() * sizeof(uint32_t),
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
          VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
      gpu::MemoryUse::DeviceOnly, "dof tile lists");
}

RayMaskImages::RayMaskImages(gpu::ImageBatch& batch, const gpu::Context& context, uint32_t w,
                             uint32_t h) {
  reach = batch.make(w, h, kScalar, "ray mask reach");
  strength = batch.make(w, h, kPair, "ray mask strength");
  tiles = makeTiles(batch, w, h, kColor, "ray mask tiles");
  dilatedTiles = makeTiles(batch, w, h, kPair, "ray mask dilated tiles");
  farRows = makeTiles(batch, w, h, kScalar, "ray mask far rows");
  farTiles = makeTiles(batch, w, h, kScalar, "ray mask far tiles");
  spread = batch.make(w, h, kColor, "ray mask spread");
  rays = batch.make(w, h, VK_FORMAT_R8_UINT, "ray mask rays");
  workList = gpu::Buffer(context,
                         sizeof(gpu::RayWorkHeader) + VkDeviceSize(w) * h * gpu::kRayWorkEntrySize,
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                             VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                         gpu::MemoryUse::DeviceOnly, "ray work list");
  workHeader = gpu::Buffer(context, sizeof(gpu::RayWorkHeader), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                           gpu::MemoryUse::Readback, "ray work list header");
  std::memset(workHeader.mapped(), 0, sizeof(gpu::RayWorkHeader));
}

HybridImages::HybridImages(gpu::ImageBatch& batch, uint32_t w, uint32_t h)
    : nearLayer(batch.make(w, h, kColor, "hybrid near layer")),
      farLayer(batch.make(w, h, kColor, "hybrid far layer")),
      farPosition(batch.make(w, h, kPrecise, "hybrid far position")),
      layerCoc(batch.make(w, h, kPair, "hybrid layer coc")),
      samplesTraced(batch.make(w, h, VK_FORMAT_R32_UINT, "hybrid samples traced")),
      history{History{batch.make(w, h, kPrecise, "history near 0"),
                      batch.make(w, h, kPrecise, "history far 0"),
                      batch.make(w, h, kPrecise, "history moments 0")},
              History{batch.make(w, h, kPrecise, "history near 1"),
                      batch.make(w, h, kPrecise, "history far 1"),
                      batch.make(w, h, kPrecise, "history moments 1")}},
      variance(batch.make(w, h, kPair, "hybrid variance")),
      reconstructedNear(batch.make(w, h, kColor, "hybrid reconstructed near")),
      reconstructedFar(batch.make(w, h, kColor, "hybrid reconstructed far")),
      difference(batch.make(w, h, kPair, "hybrid difference")),
      output(batch.make(w, h, kColor, "hybrid output")) {}

FrameImages::FrameImages(const gpu::Context& context, uint32_t w, uint32_t h)
    : width(w),
      height(h),
      batch(context),
      gbuffer(batch, context, w, h),
      dof(batch, context, w, h),
      mask(batch, context, w, h),
      hybrid(batch, w, h),
      accumulation(batch.make(w, h, kPrecise, "accumulation")),
      display(batch.make(w, h, VK_FORMAT_R8G8B8A8_UNORM, "display")),
      readback(context, VkDeviceSize(w) * h * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
               gpu::MemoryUse::Readback, "display readback") {
  // Made last, so that the images before it keep their places in memory: made among the mask's,
  // it moved every later image, and lavapipe with one thread ran a resting hybrid frame of the
  // closeup 25-35% slower in every step (231 -> 293-326 ms in hdof bench), the work unchanged.
  mask.covered = batch.make(w, h, kPair, "ray mask covered");
  batch.finish();
}

}  // namespace hdof
