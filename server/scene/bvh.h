// Bounding volume hierarchy over a scene's triangles: built on the CPU with binned SAH, flattened
// into the layout the compute shaders traverse (shared/scene_data.h). The CPU traversal here is the
// same algorithm, used for focus picking and as the reference in tests.
#pragma once

#include "scene/scene.h"

#include <optional>
#include <vector>

namespace hdof {

struct Bvh {
  std::vector<gpu::BvhNode> nodes;          // node 0 is the root
  std::vector<gpu::BvhTriangle> triangles;  // in leaf order
  uint32_t depth = 0;  // longest root-to-leaf path, in nodes; kept below gpu::kBvhStackSize
  double buildMs = 0.0;
};

struct BvhBuildOptions {
  uint32_t bins = 16;
  uint32_t maxLeafTriangles = 4;
};

Bvh buildBvh(const std::vector<gpu::Vertex>& vertices, const std::vector<uint32_t>& indices,
             const BvhBuildOptions& options = {});

struct RayHit {
  float t = 0.0f;
  uint32_t triangle = 0;     // index into the scene's index buffer / 3
  float u = 0.0f, v = 0.0f;  // barycentrics of vertices 1 and 2
};

// Closest hit with t in (tMin, tMax), or nothing. Direction need not be unit length.
std::optional<RayHit> intersect(const Bvh& bvh, const glm::vec3& origin, const glm::vec3& direction,
                                float tMin = 0.0f,
                                float tMax = std::numeric_limits<float>::infinity());

// The same query by testing every triangle: the reference for tests.
std::optional<RayHit> intersectBruteForce(const std::vector<gpu::Vertex>& vertices,
                                          const std::vector<uint32_t>& indices,
                                          const glm::vec3& origin, const glm::vec3& direction,
                                          float tMin = 0.0f,
                                          float tMax = std::numeric_limits<float>::infinity());

}  // namespace hdof
