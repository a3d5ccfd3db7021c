#include "render/ray_mask.h"

#include <shared/dof.h>
#include <shared/ray_work.h>

#include <cstring>
#include <stdexcept>

namespace hdof {

static_assert(sizeof(VkDispatchIndirectCommand) == 3 * sizeof(uint32_t) &&
              offsetof(gpu::RayWorkHeader, groupsX) == 0);

struct RayMask::Resources {
  Resources(const gpu::Context& context, uint32_t width, uint32_t height);

  uint32_t width, height;
  gpu::Image reach, strength;      // r16f: per edge pixel, its disc diameter and edge strength
  gpu::Image tiles, dilatedTiles;  // rg16f, per kDofTileSize tile: x the largest reach
  gpu::Image spread;               // rg16f: the row pass of the disc dilation
  gpu::Image rays;                 // r8ui
  gpu::Image noVariance;           // r16f, 1x1, zero
  gpu::Buffer workList;
  gpu::Buffer header;  // the work list's header, for the CPU
};

namespace {

uint32_t divideRoundingUp(uint32_t value, uint32_t divisor) {
  return (value + divisor - 1) / divisor;
}

gpu::Image makeImage(const gpu::Context& context, uint32_t width, uint32_t height, VkFormat format,
                     const char* name) {
  // Sampled and copyable too, for debug views and tests.
  return gpu::createImage2D(context, width, height, format,
                            VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                            name);
}

void computeToCompute(VkCommandBuffer cmd) {
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

}  // namespace

RayMask::Resources::Resources(const gpu::Context& context, uint32_t w, uint32_t h)
    : width(w), height(h) {
  constexpr VkFormat kTile = VK_FORMAT_R16G16_SFLOAT;
  uint32_t tilesW = divideRoundingUp(w, gpu::kDofTileSize);
  uint32_t tilesH = divideRoundingUp(h, gpu::kDofTileSize);
  reach = makeImage(context, w, h, VK_FORMAT_R16_SFLOAT, "ray mask reach");
  strength = makeImage(context, w, h, VK_FORMAT_R16_SFLOAT, "ray mask strength");
  tiles = makeImage(context, tilesW, tilesH, kTile, "ray mask tiles");
  dilatedTiles = makeImage(context, tilesW, tilesH, kTile, "ray mask dilated tiles");
  spread = makeImage(context, w, h, VK_FORMAT_R16G16_SFLOAT, "ray mask spread");
  rays = makeImage(context, w, h, VK_FORMAT_R8_UINT, "ray mask rays");
  noVariance = makeImage(context, 1, 1, VK_FORMAT_R16_SFLOAT, "ray mask no variance");
  gpu::makeGeneral(context,
                   {&reach, &strength, &tiles, &dilatedTiles, &spread, &rays, &noVariance});
  context.submitAndWait([&](VkCommandBuffer cmd) {
    VkClearColorValue zero{};
    VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cmd, noVariance.get(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &range);
  });
  workList = gpu::Buffer(context,
                         sizeof(gpu::RayWorkHeader) + VkDeviceSize(w) * h * gpu::kRayWorkEntrySize,
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                             VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                         gpu::MemoryUse::DeviceOnly, "ray work list");
  header = gpu::Buffer(context, sizeof(gpu::RayWorkHeader), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                       gpu::MemoryUse::Readback, "ray work list header");
  std::memset(header.mapped(), 0, sizeof(gpu::RayWorkHeader));
}

RayMask::RayMask(const gpu::Context& context, uint32_t width, uint32_t height)
    : context_(context),
      resources_(std::make_unique<Resources>(context, width, height)),
      edges_(context),
      tiles_(context),
      dilate_(context),
      spread_(context),
      rays_(context),
      compact_(context) {}

RayMask::~RayMask() = default;

void RayMask::resize(uint32_t width, uint32_t height) {
  if (width == resources_->width && height == resources_->height) return;
  VK_CHECK(vkQueueWaitIdle(context_.queue()));
  resources_.reset();
  resources_ = std::make_unique<Resources>(context_, width, height);
}

void RayMask::record(VkCommandBuffer cmd, gpu::GpuTimer& timer, const gpu::Buffer& frameUniforms,
                     const RenderTargets& targets, const gpu::Image* varianceOrNull,
                     bool everywhere) const {
  const Resources& r = *resources_;
  if (targets.width != r.width || targets.height != r.height)
    throw std::logic_error("RayMask::record: targets size differs from the images");
  const gpu::Image& variance = varianceOrNull ? *varianceOrNull : r.noVariance;
  // Each pass reads what the one before wrote (the first, the G-buffer's compute resolve).
  auto timed = [&](const char* name, auto&& recordPass) {
    computeToCompute(cmd);
    timer.begin(cmd, name);
    recordPass();
    timer.end(cmd);
  };
  // Last frame's ray tracer may still read the list: the fill waits for it.
  gpu::memoryBarrier(cmd,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                     VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
  vkCmdFillBuffer(cmd, r.workList.get(), 0, sizeof(gpu::RayWorkHeader), 0);
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  timed("ray_mask_edges",
        [&] { edges_.record(cmd, frameUniforms, targets.normalDepth, r.reach, r.strength); });
  timed("ray_mask_tiles", [&] { tiles_.record(cmd, frameUniforms, r.reach, r.tiles); });
  timed("ray_mask_dilate", [&] { dilate_.record(cmd, frameUniforms, r.tiles, r.dilatedTiles); });
  timed("ray_mask_spread",
        [&] { spread_.record(cmd, frameUniforms, r.reach, r.strength, r.dilatedTiles, r.spread); });
  timed("ray_mask_rays", [&] {
    rays_.record(cmd, frameUniforms, r.spread, r.dilatedTiles, variance, r.rays, everywhere);
  });
  timed("ray_mask_compact", [&] { compact_.record(cmd, frameUniforms, r.rays, r.workList); });
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT |
                         VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT |
                         VK_ACCESS_TRANSFER_READ_BIT);
  VkBufferCopy region{0, 0, sizeof(gpu::RayWorkHeader)};
  vkCmdCopyBuffer(cmd, r.workList.get(), r.header.get(), 1, &region);
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
}

const gpu::Image& RayMask::rays() const { return resources_->rays; }

const gpu::Buffer& RayMask::workList() const { return resources_->workList; }

namespace {

gpu::RayWorkHeader readHeader(const gpu::Buffer& buffer) {
  gpu::RayWorkHeader header;
  std::memcpy(&header, buffer.mapped(), sizeof(header));
  return header;
}

}  // namespace

uint32_t RayMask::listedPixels() const { return readHeader(resources_->header).count; }

uint64_t RayMask::raysShot() const { return readHeader(resources_->header).rays; }

double RayMask::coverage() const {
  return double(listedPixels()) / (double(resources_->width) * resources_->height);
}

}  // namespace hdof
