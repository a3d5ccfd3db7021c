#include "render/postprocess_dof.h"

namespace hdof {

using gpu::Grid;

PostProcessDof::PostProcessDof(const gpu::Context& context)
    : downsample_(context, "dof_downsample.comp"),
      tiles_(context, "dof_tiles.comp"),
      dilate_(context, "dof_dilate.comp"),
      prefilter_(context, "dof_prefilter.comp"),
      gather_(context, "dof_gather.comp"),
      median_(context, "dof_median.comp"),
      composite_(context, "dof_composite.comp") {}

void PostProcessDof::record(StepRecorder& steps, const GBufferImages& g, const DofImages& d) const {
  // One thread per half-resolution pixel, which also writes the CoC of its 2x2 pixels.
  steps.dispatch(downsample_,
                 {{"color", g.color},
                  {"normalDepth", g.normalDepth},
                  {"cocImage", d.coc},
                  {"halfColorCoc", d.halfColorCoc}},
                 Grid::over(d.halfColorCoc));
  steps.dispatch(tiles_, {{"cocImage", d.coc}, {"tiles", d.tiles}}, Grid::over(d.tiles));
  steps.dispatch(dilate_, {{"tiles", d.tiles}, {"dilated", d.dilatedTiles}},
                 Grid::over(d.dilatedTiles));
  steps.dispatch(prefilter_,
                 {{"halfColorCoc", d.halfColorCoc},
                  {"dilatedTiles", d.dilatedTiles},
                  {"prefiltered", d.prefiltered}},
                 Grid::over(d.prefiltered));
  // 8x8 half-resolution pixels are one tile: the kernel size is uniform across a workgroup.
  steps.dispatch(gather_,
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
  // One thread per 2x2 pixels: one per half-resolution pixel.
  steps.dispatch(composite_,
                 {{"color", g.color},
                  {"cocImage", d.coc},
                  {"farLayer", d.farFiltered},
                  {"nearLayer", d.nearFiltered},
                  {"dilatedTiles", d.dilatedTiles},
                  {"result", d.output}},
                 Grid::over(d.farFiltered));
}

}  // namespace hdof
