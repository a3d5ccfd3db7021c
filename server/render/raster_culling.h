// Frustum culling for the raster: the triangle soup is cut into runs of consecutive triangles
// (meshes keep their triangles together, so runs are compact in space) with bounds; each frame
// draws only the runs that can touch the view.
#pragma once

#include "scene/scene.h"

#include <vector>

namespace hdof {

struct TriangleRun {
  Aabb bounds;
  uint32_t firstTriangle = 0, triangleCount = 0;
};

struct TriangleRange {
  uint32_t firstTriangle = 0, triangleCount = 0;
};

std::vector<TriangleRun> buildTriangleRuns(const Scene& scene, uint32_t trianglesPerRun = 128);

// The triangles of the runs whose bounds are not wholly outside one plane of the view frustum of
// viewProj (Vulkan clip space, depth 0..1), neighbouring runs merged into one range.
std::vector<TriangleRange> visibleTriangles(const std::vector<TriangleRun>& runs,
                                            const glm::mat4& viewProj);

}  // namespace hdof
