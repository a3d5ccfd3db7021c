#include "render/postprocess_dof.h"

#include <shared/dof.h>

#include <cstddef>

namespace hdof {

using gpu::Grid;

PostProcessDof::PostProcessDof(const gpu::Context& context)
    : downsample_(context, "dof_downsample.comp"),
      tiles_(context, "dof_tiles.comp"),
      dilate_(context, "dof_dilate.comp"),
      tileLists_(context, "dof_tile_lists.comp"),
      prefilter_(context, "dof_prefilter.comp"),
      median_(context, "dof_median.comp"),
      gatherRound_(context, "dof_gather.comp"),
      gatherBladed_(context, "dof_gather.comp", nullptr, {{"kBladed", 1}}),
      compositeNarrow_(context, "dof_composite.comp", nullptr, {{"kList", gpu::kDofListNarrow}}),
      compositeWide_(context, "dof_composite.comp", nullptr, {{"kList", gpu::kDofListWide}}),
      compositeNear_(context, "dof_composite.comp", nullptr, {{"kList", gpu::kDofListNear}}),
      compositeWider_(context, "dof_composite.comp", nullptr, {{"kList", gpu::kDofListWider}}),
      compositeNearWider_(context, "dof_composite.comp", nullptr,
                          {{"kList", gpu::kDofListNearWider}}),
      compositeLayers_(context, "dof_composite_layers.comp") {}

void PostProcessDof::record(StepRecorder& steps, const GBufferImages& g, const DofImages& d,
                            bool tilesStand, bool bladed) const {
  // One thread per half-resolution pixel, which also writes the CoC of its 2x2 pixels.
  steps.dispatch(downsample_,
                 {{"color", g.color},
                  {"normalDepth", g.normalDepth},
                  {"colorCoc", d.colorCoc},
                  {"halfColorCoc", d.halfColorCoc}},
                 Grid::over(d.halfColorCoc));
  if (!tilesStand) {
    uint32_t cocChannel = 3;
    steps.dispatch(tiles_, {{"cocImage", d.colorCoc}, {"tiles", d.tiles}}, Grid::over(d.tiles),
                   cocChannel);
    steps.dispatch(dilate_, {{"tiles", d.tiles}, {"dilated", d.dilatedTiles}},
                   Grid::over(d.dilatedTiles));
    steps.step("dof_tile_lists_clear", [&](VkCommandBuffer cmd) {
      gpu::DofTileLists empty;
      for (gpu::DofTileList& list : empty.lists) list = {0, 1, 1, 0};
      vkCmdUpdateBuffer(cmd, d.tileLists.get(), 0, sizeof(empty), &empty);
    });
    steps.dispatch(tileLists_,
                   {{"tiles", d.tiles}, {"dilatedTiles", d.dilatedTiles}, {"lists", d.tileLists}},
                   Grid::over(d.tiles));
  }
  steps.dispatch(prefilter_,
                 {{"halfColorCoc", d.halfColorCoc},
                  {"dilatedTiles", d.dilatedTiles},
                  {"prefiltered", d.prefiltered}},
                 Grid::over(d.prefiltered));
  // 8x8 half-resolution pixels are one tile: the kernel size is uniform across a workgroup.
  steps.dispatch(bladed ? gatherBladed_ : gatherRound_,
                 {{"prefiltered", d.prefiltered},
                  {"dilatedTiles", d.dilatedTiles},
                  {"farLayer", d.farLayer},
                  {"nearLayer", d.nearLayer}},
                 Grid::over(d.farLayer));
  steps.dispatch(median_,
                 {{"farLayer", d.farLayer},
                  {"nearLayer", d.nearLayer},
                  {"dilatedTiles", d.dilatedTiles},
                  {"farFiltered", d.farFiltered},
                  {"nearFiltered", d.nearFiltered}},
                 Grid::over(d.farFiltered));
  // One thread per 2x2 pixels, a workgroup per listed tile.
  std::initializer_list<gpu::Bind> compositeBinds{
      {"colorCoc", d.colorCoc},         {"farLayer", d.farFiltered}, {"nearLayer", d.nearFiltered},
      {"dilatedTiles", d.dilatedTiles}, {"lists", d.tileLists},      {"result", d.output}};
  auto composite = [&](const gpu::ComputeProgram& program, uint32_t list, const char* name) {
    VkDeviceSize arguments = offsetof(gpu::DofTileLists, lists) + list * sizeof(gpu::DofTileList);
    steps.dispatch(program, compositeBinds, Grid::indirect(d.tileLists, arguments), {}, name);
  };
  composite(compositeNarrow_, gpu::kDofListNarrow, "dof_composite_narrow");
  composite(compositeWide_, gpu::kDofListWide, "dof_composite_wide");
  composite(compositeNear_, gpu::kDofListNear, "dof_composite_near");
  composite(compositeWider_, gpu::kDofListWider, "dof_composite_wider");
  composite(compositeNearWider_, gpu::kDofListNearWider, "dof_composite_near_wider");
  composite(compositeLayers_, gpu::kDofListLayers, "dof_composite_layers");
}

}  // namespace hdof
