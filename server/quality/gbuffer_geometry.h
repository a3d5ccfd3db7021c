// The pinhole frame's geometry on the CPU: linear depth and world normals of the G-buffer, which
// the quality regions (occlusion_mask, edge_band) are computed from.
#pragma once

#include "gpu/context.h"
#include "render/frame_pipeline.h"

#include <glm/vec3.hpp>

#include <vector>

namespace hdof {

struct GBufferGeometry {
  std::vector<float> linearDepth;  // metres, kBackgroundDepth where nothing is; row-major
  std::vector<glm::vec3> normals;  // world normals, zero where nothing is; row-major
};

// Reads gbuffer.normalDepth of the last frame the pipeline rendered through the G-buffer (e.g. a
// pinhole frame), waiting for the GPU.
GBufferGeometry readGBufferGeometry(const gpu::Context& context, const FramePipeline& pipeline);

}  // namespace hdof
