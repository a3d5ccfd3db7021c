#include "scene/gpu_bvh.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace hdof {
namespace {

constexpr uint32_t kGridMax = 255;  // quantised planes are bytes

float gridStep(uint32_t biasedExponent) { return std::bit_cast<float>(biasedExponent << 23); }

// A grid plane's position, computed as the shader does: q * step is exact (8 bits times a power
// of two), so the sum rounds once, fused or not.
float gridPlane(float origin, uint32_t q, float step) {
  return origin + static_cast<float>(q) * step;
}

uint32_t byteOf(uint32_t word, uint32_t k) { return (word >> (8 * k)) & 0xffu; }

// The smallest power-of-two step (as a float's biased exponent) whose 255 steps from `low` reach
// `high`.
uint32_t gridExponent(float low, float high) {
  int exponent = 0;
  std::frexp((high - low) / static_cast<float>(kGridMax), &exponent);
  auto biased = static_cast<uint32_t>(std::clamp(exponent + 127, 1, 254));
  while (biased < 254 && gridPlane(low, kGridMax, gridStep(biased)) < high) ++biased;
  return biased;
}

class WideNodePacker {
 public:
  explicit WideNodePacker(const Bvh& bvh) : nodes_(bvh.nodes) {
    wide_.reserve(nodes_.size() / 3 + 1);
  }

  std::vector<gpu::BvhWideNode> pack() && {
    if (nodes_.at(0).triangleCount > 0 || nodes_.size() == 1) {
      wide_.push_back(packNode({0}));
    } else {
      packChildrenOf(0);
    }
    return std::move(wide_);
  }

 private:
  // The built tree's nodes that become the wide node's children: the interior node's two
  // children, then, while there is room, the interior one of largest area replaced by its own.
  std::vector<uint32_t> collapse(uint32_t node) const {
    uint32_t left = nodes_[node].leftOrFirst;
    std::vector<uint32_t> children{left, left + 1};
    while (children.size() < gpu::kBvhWidth) {
      auto widest = children.end();
      float widestArea = -1.0f;
      for (auto it = children.begin(); it != children.end(); ++it) {
        const gpu::BvhNode& child = nodes_[*it];
        float area = Aabb{child.boundsMin, child.boundsMax}.surfaceArea();
        if (child.triangleCount == 0 && area > widestArea) {
          widest = it;
          widestArea = area;
        }
      }
      if (widest == children.end()) break;
      uint32_t grandchild = nodes_[*widest].leftOrFirst;
      *widest = grandchild;
      children.push_back(grandchild + 1);
    }
    return children;
  }

  // Appends the wide node of an interior node, then its subtrees depth first, so that the first
  // interior child's node follows its parent's; returns its index.
  uint32_t packChildrenOf(uint32_t node) {
    std::vector<uint32_t> children = collapse(node);
    auto index = static_cast<uint32_t>(wide_.size());
    wide_.emplace_back();
    gpu::BvhWideNode packed = packNode(children);
    for (uint32_t k = 0; k < children.size(); ++k) {
      if (nodes_[children[k]].triangleCount == 0) packed.links[k] = packChildrenOf(children[k]);
    }
    wide_[index] = packed;  // after the recursion, which may have moved wide_
    return index;
  }

  // A leaf's triangle count, gpu::kBvhInteriorChild, or gpu::kBvhEmptyChild for the root of a
  // tree without triangles (an only child that is no leaf).
  uint32_t childInfo(uint32_t child, size_t siblings) const {
    const gpu::BvhNode& node = nodes_[child];
    if (node.triangleCount > 0) return node.triangleCount;
    return siblings == 1 ? gpu::kBvhEmptyChild : gpu::kBvhInteriorChild;
  }

  // A wide node of the given children, interior ones without their links yet.
  gpu::BvhWideNode packNode(const std::vector<uint32_t>& children) const {
    gpu::BvhWideNode packed{};
    Aabb all;
    for (uint32_t child : children)
      all.grow(Aabb{nodes_[child].boundsMin, nodes_[child].boundsMax});
    packed.origin = all.min;
    glm::vec3 step;
    for (int axis = 0; axis < 3; ++axis) {
      uint32_t exponent = gridExponent(all.min[axis], all.max[axis]);
      packed.exponents |= exponent << (8 * axis);
      step[axis] = gridStep(exponent);
    }
    uint32_t* lows[3] = {&packed.lowX, &packed.lowY, &packed.lowZ};
    uint32_t* highs[3] = {&packed.highX, &packed.highY, &packed.highZ};
    for (uint32_t k = 0; k < gpu::kBvhWidth; ++k) {
      uint32_t info =
          k < children.size() ? childInfo(children[k], children.size()) : gpu::kBvhEmptyChild;
      packed.childInfo[k / 2] |= info << (16 * (k % 2));
      if (info == gpu::kBvhEmptyChild) continue;
      const gpu::BvhNode& child = nodes_[children[k]];
      if (info != gpu::kBvhInteriorChild) packed.links[k] = child.leftOrFirst;
      for (int axis = 0; axis < 3; ++axis) {
        float origin = all.min[axis], s = step[axis];
        auto quantise = [&](float value, float (*round)(float)) {
          return std::clamp(round((value - origin) / s), 0.0f, static_cast<float>(kGridMax));
        };
        auto low = static_cast<uint32_t>(quantise(child.boundsMin[axis], std::floor));
        auto high = static_cast<uint32_t>(quantise(child.boundsMax[axis], std::ceil));
        // Division rounds: step outwards until the decoded planes hold the box.
        while (low > 0 && gridPlane(origin, low, s) > child.boundsMin[axis]) --low;
        while (high < kGridMax && gridPlane(origin, high, s) < child.boundsMax[axis]) ++high;
        *lows[axis] |= low << (8 * k);
        *highs[axis] |= high << (8 * k);
      }
    }
    return packed;
  }

  const std::vector<gpu::BvhNode>& nodes_;
  std::vector<gpu::BvhWideNode> wide_;
};

}  // namespace

std::vector<gpu::BvhWideNode> packBvhWideNodes(const Bvh& bvh) {
  return WideNodePacker(bvh).pack();
}

uint32_t wideChildInfo(const gpu::BvhWideNode& node, uint32_t k) {
  return (node.childInfo[k / 2] >> (16 * (k % 2))) & 0xffffu;
}

Aabb wideChildBounds(const gpu::BvhWideNode& node, uint32_t k) {
  const uint32_t lows[3] = {node.lowX, node.lowY, node.lowZ};
  const uint32_t highs[3] = {node.highX, node.highY, node.highZ};
  Aabb bounds;
  for (int axis = 0; axis < 3; ++axis) {
    float step = gridStep(byteOf(node.exponents, axis));
    bounds.min[axis] = gridPlane(node.origin[axis], byteOf(lows[axis], k), step);
    bounds.max[axis] = gridPlane(node.origin[axis], byteOf(highs[axis], k), step);
  }
  return bounds;
}

}  // namespace hdof
