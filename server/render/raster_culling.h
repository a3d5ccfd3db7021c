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
// viewProj (Vulkan clip space, depth 0..1). Neighbouring runs wholly inside it are merged into one
// range; a run across one of its planes is a range of its own, so that the clipping its triangles
// may need is confined to its own draw (lavapipe, for one, sends a whole draw's batch of vertices
// through its clipper when one of them is outside, and revisits the batch at every flush of it:
// measured 20% of the visibility step on the living room before they were split off).
std::vector<TriangleRange> visibleTriangles(const std::vector<TriangleRun>& runs,
                                            const glm::mat4& viewProj);

}  // namespace hdof
