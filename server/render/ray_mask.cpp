#include "render/ray_mask.h"

#include <cstring>

namespace hdof {

using gpu::Grid;

static_assert(sizeof(VkDispatchIndirectCommand) == 3 * sizeof(uint32_t) &&
              offsetof(gpu::RayWorkHeader, groupsX) == 0);

RayMask::RayMask(const gpu::Context& context)
    : edges_(context, "ray_mask_edges.comp"),
      tiles_(context, "dof_tiles.comp"),
      dilate_(context, "dof_dilate.comp"),
      farRows_(context, "ray_mask_far.comp", nullptr, {{"kColumns", 0}}),
      farColumns_(context, "ray_mask_far.comp", nullptr, {{"kColumns", 1}}),
      spread_(context, "ray_mask_spread.comp"),
      columns_(context, "ray_mask_columns.comp"),
      rays_(context, "ray_mask_rays.comp"),
      indirect_(context, "ray_mask_indirect.comp"),
      noVarianceBatch_(context),
      noVariance_(noVarianceBatch_.make(1, 1, VK_FORMAT_R16G16_SFLOAT, "ray mask no variance")) {
  noVarianceBatch_.finish();
}

void RayMask::record(StepRecorder& steps, const GBufferImages& g, const RayMaskImages& m,
                     const gpu::Image* varianceOrNull, RayMaskOptions options) const {
  // Last frame's ray tracer may still read the list: the step barrier orders the fill after it.
  steps.step("ray_mask_clear", [&](VkCommandBuffer cmd) {
    vkCmdFillBuffer(cmd, m.workList.get(), 0, sizeof(gpu::RayWorkHeader), 0);
  });
  if (!options.edgesStand) {
    steps.dispatch(edges_,
                   {{"normalDepth", g.normalDepth}, {"reach", m.reach}, {"strength", m.strength}},
                   Grid::over(m.reach));
    uint32_t reachChannel = 0;
    steps.dispatch(tiles_, {{"cocImage", m.reach}, {"tiles", m.tiles}}, Grid::over(m.tiles),
                   reachChannel, "ray_mask_tiles");
    steps.dispatch(dilate_, {{"tiles", m.tiles}, {"dilated", m.dilatedTiles}},
                   Grid::over(m.dilatedTiles), {}, "ray_mask_dilate");
    steps.dispatch(farRows_, {{"source", m.tiles}, {"result", m.farRows}}, Grid::over(m.farRows),
                   {}, "ray_mask_far_rows");
    steps.dispatch(farColumns_, {{"source", m.farRows}, {"result", m.farTiles}},
                   Grid::over(m.farTiles), {}, "ray_mask_far_columns");
    steps.dispatch(spread_,
                   {{"reach", m.reach},
                    {"strength", m.strength},
                    {"dilatedTiles", m.dilatedTiles},
                    {"spread", m.spread}},
                   Grid::over(m.spread));
    steps.dispatch(columns_,
                   {{"spread", m.spread},
                    {"dilatedTiles", m.dilatedTiles},
                    {"farTiles", m.farTiles},
                    {"normalDepth", g.normalDepth},
                    {"covered", m.covered}},
                   Grid::over(m.covered));
  }
  struct {
    uint32_t everywhere, inTurns;
  } raysPush{options.everywhere ? 1u : 0u, options.inTurns ? 1u : 0u};
  steps.dispatch(rays_,
                 {{"covered", m.covered},
                  {"variance", varianceOrNull ? *varianceOrNull : noVariance_},
                  {"rays", m.rays},
                  {"workList", m.workList},
                  {"normalDepth", g.normalDepth}},
                 Grid::over(m.rays), raysPush);
  // The count is final only once every workgroup has appended.
  steps.dispatch(indirect_, {{"workList", m.workList}}, Grid::threads(1));
  steps.step("ray_mask_readback", [&](VkCommandBuffer cmd) {
    gpu::copyBufferToHost(cmd, m.workList, m.workHeader, sizeof(gpu::RayWorkHeader));
  });
}

gpu::RayWorkHeader readWorkHeader(const RayMaskImages& mask) {
  gpu::RayWorkHeader header;
  std::memcpy(&header, mask.workHeader.mapped(), sizeof(header));
  return header;
}

}  // namespace hdof
