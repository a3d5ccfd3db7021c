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
  uint32_t depth = 0;                       // longest root-to-leaf path, in nodes
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

// The slab test of the traversals: the ray's entry distance into the box, or infinity when it
// misses it within (tMin, tMax). The exit distance is widened by a few ulps, so that rounding
// cannot hide a triangle lying in a face of the box. `inverse` is safeInverse(direction), whose
// zero components become tiny ones, so that the test never computes 0 * inf.
glm::vec3 safeInverse(const glm::vec3& direction);
float enterBox(const Aabb& box, const glm::vec3& origin, const glm::vec3& inverse, float tMin,
               float tMax);

// The same query by testing every triangle: the reference for tests.
std::optional<RayHit> intersectBruteForce(const std::vector<gpu::Vertex>& vertices,
                                          const std::vector<uint32_t>& indices,
                                          const glm::vec3& origin, const glm::vec3& direction,
                                          float tMin = 0.0f,
                                          float tMax = std::numeric_limits<float>::infinity());

}  // namespace hdof
