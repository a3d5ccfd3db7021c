// The post-process depth of field (Jimenez 2014, "Next Generation Post Processing in Call of
// Duty: Advanced Warfare") from the G-buffer's sharp colour and depth: CoC and half-resolution
// downsample, CoC tiles, tile dilation, prefilter, scatter-as-gather into a near and a far layer,
// median, and a full-resolution composite in passes over lists of tiles, five of them for the
// tiles with full-resolution blurs by how far those read, one for the others (shaders/dof_*.comp).
#pragma once

#include "render/frame_images.h"
#include "render/steps.h"

namespace hdof {

class PostProcessDof {
 public:
  explicit PostProcessDof(const gpu::Context& context);
  // Reads gbuffer.color and gbuffer.normalDepth; writes dof, its result in dof.output.
  // tilesStand: dof.tiles, .dilatedTiles and .tileLists, which follow the CoC alone (depth and
  // lens), are those of this G-buffer's depth through this lens already. bladed: the aperture
  // has blades (FrameUniforms::bladeCount 3 or more).
  void record(StepRecorder& steps, const GBufferImages& gbuffer, const DofImages& dof,
              bool tilesStand, bool bladed) const;

 private:
  gpu::ComputeProgram downsample_, tiles_, dilate_, tileLists_, prefilter_, median_;
  // dof_gather.comp made for a round aperture and for one of blades.
  gpu::ComputeProgram gatherRound_, gatherBladed_;
  // dof_composite.comp made for the narrow, wide, near, wider and near-wider lists of tiles
  // (shared/dof.h).
  gpu::ComputeProgram compositeNarrow_, compositeWide_, compositeNear_, compositeWider_,
      compositeNearWider_, compositeLayers_;
};

}  // namespace hdof
