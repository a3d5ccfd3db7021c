#include "scene/bvh.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

namespace hdof {

namespace {

// Root-to-leaf paths stay shorter than the GPU traversal's stack: deeper nodes become leaves
// (unless they hold more triangles than a leaf can).
constexpr uint32_t kMaxDepth = gpu::kBvhStackSize - 1;
constexpr uint32_t kMaxBins = 64;

struct PendingNode {
  uint32_t node, first, count, depth;
};

struct Bin {
  Aabb bounds;
  uint32_t count = 0;
};

struct Split {
  int axis = -1;
  uint32_t bin = 0;  // centroids in bins below this one go left
  float binMin = 0.0f, binScale = 0.0f;
  float cost = std::numeric_limits<float>::infinity();
  Aabb leftBounds, rightBounds;
};

class BvhBuilder {
 public:
  BvhBuilder(const std::vector<gpu::Vertex>& vertices, const std::vector<uint32_t>& indices,
             const BvhBuildOptions& options)
      : vertices_(vertices),
        indices_(indices),
        binCount_(std::clamp(options.bins, 2u, kMaxBins)),
        maxLeafTriangles_(std::max(options.maxLeafTriangles, 1u)) {}

  Bvh build() {
    Bvh bvh;
    uint32_t triangleCount = static_cast<uint32_t>(indices_.size() / 3);
    computeTriangleBounds(triangleCount);
    Aabb rootBounds;
    for (const Aabb& bounds : triangleBounds_) rootBounds.grow(bounds);
    nodes_.reserve(triangleCount > 0 ? 2 * size_t{triangleCount} - 1 : 1);
    nodes_.push_back(makeNode(rootBounds));

    std::vector<PendingNode> stack;
    stack.push_back({0, 0, triangleCount, 1});
    while (!stack.empty()) {
      PendingNode pending = stack.back();
      stack.pop_back();
      bvh.depth = std::max(bvh.depth, pending.depth);
      Split split;
      if (pending.count > maxLeafTriangles_ && pending.depth < kMaxDepth) {
        split = findSplit(pending.node, pending.first, pending.count);
      }
      uint32_t leftCount = 0;
      if (split.axis >= 0) {
        leftCount = partition(pending.first, pending.count, split);
      } else if (pending.count > gpu::kBvhMaxLeafTriangles) {
        // More triangles than a leaf can hold (all in one place, or too deep): halve the range.
        leftCount = pending.count / 2;
        split.leftBounds = boundsOf(pending.first, leftCount);
        split.rightBounds = boundsOf(pending.first + leftCount, pending.count - leftCount);
      } else {
        nodes_[pending.node].leftOrFirst = pending.first;
        nodes_[pending.node].triangleCount = pending.count;
        continue;
      }
      uint32_t left = static_cast<uint32_t>(nodes_.size());
      nodes_[pending.node].leftOrFirst = left;
      nodes_[pending.node].triangleCount = 0;
      nodes_.push_back(makeNode(split.leftBounds));
      nodes_.push_back(makeNode(split.rightBounds));
      stack.push_back({left, pending.first, leftCount, pending.depth + 1});
      stack.push_back(
          {left + 1, pending.first + leftCount, pending.count - leftCount, pending.depth + 1});
    }

    bvh.nodes = std::move(nodes_);
    bvh.triangles.reserve(triangleCount);
    for (uint32_t triangle : order_) bvh.triangles.push_back(leafTriangle(triangle));
    return bvh;
  }

 private:
  static gpu::BvhNode makeNode(const Aabb& bounds) {
    return gpu::BvhNode{bounds.min, 0u, bounds.max, 0u};
  }

  void computeTriangleBounds(uint32_t triangleCount) {
    triangleBounds_.resize(triangleCount);
    centroids_.resize(triangleCount);
    order_.resize(triangleCount);
    for (uint32_t t = 0; t < triangleCount; ++t) {
      Aabb bounds;
      for (int k = 0; k < 3; ++k) bounds.grow(vertices_[indices_[3 * t + k]].position);
      triangleBounds_[t] = bounds;
      centroids_[t] = bounds.center();
      order_[t] = t;
    }
  }

  Aabb boundsOf(uint32_t first, uint32_t count) const {
    Aabb bounds;
    for (uint32_t i = first; i < first + count; ++i) bounds.grow(triangleBounds_[order_[i]]);
    return bounds;
  }

  // The bin of a centroid along an axis; binning and partitioning must agree exactly.
  uint32_t binOf(float centroid, float binMin, float binScale) const {
    auto bin = static_cast<uint32_t>(std::max((centroid - binMin) * binScale, 0.0f));
    return std::min(bin, binCount_ - 1);
  }

  // The cheapest binned SAH split, or axis -1 when keeping a leaf is cheaper. Costs are in units
  // of one triangle test, with a node traversal costing as much as one.
  Split findSplit(uint32_t node, uint32_t first, uint32_t count) {
    Aabb centroidBounds;
    for (uint32_t i = first; i < first + count; ++i) centroidBounds.grow(centroids_[order_[i]]);
    const gpu::BvhNode& parent = nodes_[node];
    float parentArea = Aabb{parent.boundsMin, parent.boundsMax}.surfaceArea();

    Split best;
    for (int axis = 0; axis < 3; ++axis) {
      float extent = centroidBounds.max[axis] - centroidBounds.min[axis];
      if (!(extent > 0.0f)) continue;
      float binMin = centroidBounds.min[axis];
      float binScale = static_cast<float>(binCount_) / extent;
      std::array<Bin, kMaxBins> bins{};
      for (uint32_t i = first; i < first + count; ++i) {
        uint32_t triangle = order_[i];
        Bin& bin = bins[binOf(centroids_[triangle][axis], binMin, binScale)];
        bin.bounds.grow(triangleBounds_[triangle]);
        ++bin.count;
      }
      // Sweep from the right to know each split's right side, then from the left.
      std::array<Aabb, kMaxBins> rightBounds;
      std::array<uint32_t, kMaxBins> rightCount{};
      Aabb sweep;
      uint32_t sweepCount = 0;
      for (uint32_t b = binCount_ - 1; b > 0; --b) {
        sweep.grow(bins[b].bounds);
        sweepCount += bins[b].count;
        rightBounds[b] = sweep;
        rightCount[b] = sweepCount;
      }
      Aabb leftBounds;
      uint32_t leftCount = 0;
      for (uint32_t b = 1; b < binCount_; ++b) {
        leftBounds.grow(bins[b - 1].bounds);
        leftCount += bins[b - 1].count;
        if (leftCount == 0 || rightCount[b] == 0) continue;
        float cost = leftBounds.surfaceArea() * static_cast<float>(leftCount) +
                     rightBounds[b].surfaceArea() * static_cast<float>(rightCount[b]);
        if (cost < best.cost) {
          best = Split{axis, b, binMin, binScale, cost, leftBounds, rightBounds[b]};
        }
      }
    }
    if (best.axis < 0 || !(parentArea > 0.0f)) return best;
    best.cost = 1.0f + best.cost / parentArea;
    if (best.cost >= static_cast<float>(count)) best.axis = -1;
    return best;
  }

  uint32_t partition(uint32_t first, uint32_t count, const Split& split) {
    auto middle = std::partition(
        order_.begin() + first, order_.begin() + first + count, [&](uint32_t triangle) {
          return binOf(centroids_[triangle][split.axis], split.binMin, split.binScale) < split.bin;
        });
    return static_cast<uint32_t>(middle - (order_.begin() + first));
  }

  gpu::BvhTriangle leafTriangle(uint32_t triangle) const {
    glm::vec3 v0 = vertices_[indices_[3 * triangle]].position;
    glm::vec3 v1 = vertices_[indices_[3 * triangle + 1]].position;
    glm::vec3 v2 = vertices_[indices_[3 * triangle + 2]].position;
    return gpu::BvhTriangle{v0, triangle, v1 - v0, 0.0f, v2 - v0, 0.0f};
  }

  const std::vector<gpu::Vertex>& vertices_;
  const std::vector<uint32_t>& indices_;
  uint32_t binCount_;
  uint32_t maxLeafTriangles_;
  std::vector<Aabb> triangleBounds_;
  std::vector<glm::vec3> centroids_;
  std::vector<uint32_t> order_;  // triangle numbers, partitioned in place into leaf order
  std::vector<gpu::BvhNode> nodes_;
};

}  // namespace

Bvh buildBvh(const std::vector<gpu::Vertex>& vertices, const std::vector<uint32_t>& indices,
             const BvhBuildOptions& options) {
  auto start = std::chrono::steady_clock::now();
  Bvh bvh = BvhBuilder(vertices, indices, options).build();
  bvh.buildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return bvh;
}

namespace {

Aabb nodeBounds(const gpu::BvhNode& node) { return {node.boundsMin, node.boundsMax}; }

// Möller–Trumbore, double-sided: the GPU traversal uses the same expressions in the same order,
// so both see the same hits.
bool intersectTriangle(const glm::vec3& origin, const glm::vec3& direction, const glm::vec3& v0,
                       const glm::vec3& edge1, const glm::vec3& edge2, float tMin, float tMax,
                       RayHit& hit) {
  glm::vec3 p = glm::cross(direction, edge2);
  float determinant = glm::dot(edge1, p);
  // Nearly parallel rays and sub-micrometre triangles count as misses, as on the GPU.
  if (std::abs(determinant) < 1e-12f) return false;
  float inverseDeterminant = 1.0f / determinant;
  glm::vec3 toOrigin = origin - v0;
  float u = glm::dot(toOrigin, p) * inverseDeterminant;
  if (u < 0.0f || u > 1.0f) return false;
  glm::vec3 q = glm::cross(toOrigin, edge1);
  float v = glm::dot(direction, q) * inverseDeterminant;
  if (v < 0.0f || u + v > 1.0f) return false;
  float t = glm::dot(edge2, q) * inverseDeterminant;
  if (!(t > tMin && t < tMax)) return false;
  hit.t = t;
  hit.u = u;
  hit.v = v;
  return true;
}

}  // namespace

glm::vec3 safeInverse(const glm::vec3& direction) {
  glm::vec3 inverse;
  for (int axis = 0; axis < 3; ++axis) {
    float d = direction[axis];
    inverse[axis] = 1.0f / (std::abs(d) > 1e-20f ? d : std::copysign(1e-20f, d));
  }
  return inverse;
}

float enterBox(const Aabb& box, const glm::vec3& origin, const glm::vec3& inverse, float tMin,
               float tMax) {
  glm::vec3 t0 = (box.min - origin) * inverse;
  glm::vec3 t1 = (box.max - origin) * inverse;
  glm::vec3 near = glm::min(t0, t1), far = glm::max(t0, t1);
  float enter = std::max(std::max(near.x, near.y), std::max(near.z, tMin));
  float exit = std::min(std::min(far.x, far.y), std::min(far.z, tMax));
  exit += std::abs(exit) * 4e-7f;
  return enter <= exit ? enter : std::numeric_limits<float>::infinity();
}

std::optional<RayHit> intersect(const Bvh& bvh, const glm::vec3& origin, const glm::vec3& direction,
                                float tMin, float tMax) {
  if (bvh.triangles.empty()) return std::nullopt;
  glm::vec3 inverse = safeInverse(direction);
  std::optional<RayHit> closest;
  float closestT = tMax;
  RayHit candidate;

  std::vector<uint32_t> stack(bvh.depth);  // at most a node per level is pending
  uint32_t stackSize = 0;
  uint32_t node = 0;
  if (std::isinf(enterBox(nodeBounds(bvh.nodes[0]), origin, inverse, tMin, closestT)))
    return std::nullopt;
  while (true) {
    const gpu::BvhNode& current = bvh.nodes[node];
    if (current.triangleCount > 0) {
      for (uint32_t i = current.leftOrFirst; i < current.leftOrFirst + current.triangleCount; ++i) {
        const gpu::BvhTriangle& triangle = bvh.triangles[i];
        if (intersectTriangle(origin, direction, triangle.v0, triangle.edge1, triangle.edge2, tMin,
                              closestT, candidate)) {
          candidate.triangle = triangle.index;
          closest = candidate;
          closestT = candidate.t;
        }
      }
    } else {
      uint32_t near = current.leftOrFirst, far = current.leftOrFirst + 1;
      float enterNear = enterBox(nodeBounds(bvh.nodes[near]), origin, inverse, tMin, closestT);
      float enterFar = enterBox(nodeBounds(bvh.nodes[far]), origin, inverse, tMin, closestT);
      if (enterFar < enterNear) {
        std::swap(near, far);
        std::swap(enterNear, enterFar);
      }
      if (!std::isinf(enterNear)) {
        if (!std::isinf(enterFar)) stack[stackSize++] = far;
        node = near;
        continue;
      }
    }
    // Pop the next subtree that can still hold something closer than the current hit.
    bool found = false;
    while (stackSize > 0 && !found) {
      node = stack[--stackSize];
      found = !std::isinf(enterBox(nodeBounds(bvh.nodes[node]), origin, inverse, tMin, closestT));
    }
    if (!found) return closest;
  }
}

std::optional<RayHit> intersectBruteForce(const std::vector<gpu::Vertex>& vertices,
                                          const std::vector<uint32_t>& indices,
                                          const glm::vec3& origin, const glm::vec3& direction,
                                          float tMin, float tMax) {
  std::optional<RayHit> closest;
  RayHit candidate;
  for (uint32_t triangle = 0; triangle < indices.size() / 3; ++triangle) {
    glm::vec3 v0 = vertices[indices[3 * triangle]].position;
    glm::vec3 edge1 = vertices[indices[3 * triangle + 1]].position - v0;
    glm::vec3 edge2 = vertices[indices[3 * triangle + 2]].position - v0;
    if (intersectTriangle(origin, direction, v0, edge1, edge2, tMin, tMax, candidate)) {
      candidate.triangle = triangle;
      closest = candidate;
      tMax = candidate.t;
    }
  }
  return closest;
}

}  // namespace hdof
