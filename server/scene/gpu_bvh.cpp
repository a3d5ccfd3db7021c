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

// A float rounded down (towards minus infinity) to one whose low byte is zero, that byte then
// free for the grid's exponent.
float roundDownToHighBits(float value) {
  uint32_t bits = std::bit_cast<uint32_t>(value);
  uint32_t high = bits & ~0xffu;
  // Clearing bits lowers a positive float's magnitude, and a negative float's too: those step
  // one unit of the kept bits further from zero instead.
  if (value < 0.0f && high != bits) high += 0x100u;
  return std::bit_cast<float>(high);
}

float originOf(const gpu::BvhWideNode& node, int axis) {
  return std::bit_cast<float>(node.origin[axis] & ~0xffu);
}

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
  explicit WideNodePacker(const Bvh& bvh) : nodes_(bvh.nodes), triangles_(bvh.triangles) {
    packed_.nodes.reserve(nodes_.size() / 3 + 1);
    packed_.triangles.reserve(triangles_.size());
  }

  PackedBvh pack() && {
    packed_.nodes.emplace_back();
    if (nodes_.at(0).triangleCount > 0 || nodes_.size() == 1) {
      fill(0, {0});
    } else {
      fill(0, collapse(0));
    }
    return std::move(packed_);
  }

 private:
  // Packs the wide node of the given children into slot `index`: its leaves' triangles appended
  // to the packed triangles, its interior children given the next consecutive slots, then each
  // of them filled the same way.
  void fill(uint32_t index, const std::vector<uint32_t>& children) {
    gpu::BvhWideNode node = packNode(children);
    node.firstTriangle = static_cast<uint32_t>(packed_.triangles.size());
    node.firstNode = static_cast<uint32_t>(packed_.nodes.size());
    std::vector<uint32_t> interior;
    for (uint32_t k = 0; k < children.size(); ++k) {
      uint32_t info = wideChildInfo(node, k);
      if (info == gpu::kBvhInteriorChild) {
        interior.push_back(children[k]);
      } else if (info != gpu::kBvhEmptyChild) {
        const gpu::BvhNode& leaf = nodes_[children[k]];
        packed_.triangles.insert(packed_.triangles.end(),
                                 triangles_.begin() + leaf.leftOrFirst,
                                 triangles_.begin() + leaf.leftOrFirst + leaf.triangleCount);
      }
    }
    packed_.nodes.resize(packed_.nodes.size() + interior.size());
    packed_.nodes[index] = node;  // before the recursion, which may move the vector
    for (uint32_t i = 0; i < interior.size(); ++i) fill(node.firstNode + i, collapse(interior[i]));
  }

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

  // A leaf's triangle count, gpu::kBvhInteriorChild, or gpu::kBvhEmptyChild for the root of a
  // tree without triangles (an only child that is no leaf).
  uint32_t childInfo(uint32_t child, size_t siblings) const {
    const gpu::BvhNode& node = nodes_[child];
    if (node.triangleCount > 0) return node.triangleCount;
    return siblings == 1 ? gpu::kBvhEmptyChild : gpu::kBvhInteriorChild;
  }

  // A wide node of the given children, without its first node and triangle yet.
  gpu::BvhWideNode packNode(const std::vector<uint32_t>& children) const {
    gpu::BvhWideNode packed{};
    Aabb all;
    for (uint32_t child : children)
      all.grow(Aabb{nodes_[child].boundsMin, nodes_[child].boundsMax});
    glm::vec3 origin, step;
    for (int axis = 0; axis < 3; ++axis) {
      origin[axis] = roundDownToHighBits(all.min[axis]);
      uint32_t exponent = gridExponent(origin[axis], all.max[axis]);
      packed.origin[axis] = std::bit_cast<uint32_t>(origin[axis]) | exponent;
      step[axis] = gridStep(exponent);
    }
    uint32_t* lows[3] = {&packed.lowX, &packed.lowY, &packed.lowZ};
    uint32_t* highs[3] = {&packed.highX, &packed.highY, &packed.highZ};
    for (uint32_t k = 0; k < gpu::kBvhWidth; ++k) {
      uint32_t info =
          k < children.size() ? childInfo(children[k], children.size()) : gpu::kBvhEmptyChild;
      packed.childInfo |= info << (8 * k);
      if (info == gpu::kBvhEmptyChild) continue;
      const gpu::BvhNode& child = nodes_[children[k]];
      for (int axis = 0; axis < 3; ++axis) {
        float o = origin[axis], s = step[axis];
        auto quantise = [&](float value, float (*round)(float)) {
          return std::clamp(round((value - o) / s), 0.0f, static_cast<float>(kGridMax));
        };
        auto low = static_cast<uint32_t>(quantise(child.boundsMin[axis], std::floor));
        auto high = static_cast<uint32_t>(quantise(child.boundsMax[axis], std::ceil));
        // Division rounds: step outwards until the decoded planes hold the box.
        while (low > 0 && gridPlane(o, low, s) > child.boundsMin[axis]) --low;
        while (high < kGridMax && gridPlane(o, high, s) < child.boundsMax[axis]) ++high;
        *lows[axis] |= low << (8 * k);
        *highs[axis] |= high << (8 * k);
      }
    }
    return packed;
  }

  const std::vector<gpu::BvhNode>& nodes_;
  const std::vector<gpu::BvhTriangle>& triangles_;
  PackedBvh packed_;
};

}  // namespace

PackedBvh packBvh(const Bvh& bvh) { return WideNodePacker(bvh).pack(); }

uint32_t wideChildInfo(const gpu::BvhWideNode& node, uint32_t k) {
  return byteOf(node.childInfo, k);
}

uint32_t wideChildLink(const gpu::BvhWideNode& node, uint32_t k) {
  uint32_t interiorBefore = 0, trianglesBefore = 0;
  for (uint32_t j = 0; j < k; ++j) {
    uint32_t info = wideChildInfo(node, j);
    if (info == gpu::kBvhInteriorChild)
      ++interiorBefore;
    else if (info != gpu::kBvhEmptyChild)
      trianglesBefore += info;
  }
  return wideChildInfo(node, k) == gpu::kBvhInteriorChild ? node.firstNode + interiorBefore
                                                          : node.firstTriangle + trianglesBefore;
}

Aabb wideChildBounds(const gpu::BvhWideNode& node, uint32_t k) {
  const uint32_t lows[3] = {node.lowX, node.lowY, node.lowZ};
  const uint32_t highs[3] = {node.highX, node.highY, node.highZ};
  Aabb bounds;
  for (int axis = 0; axis < 3; ++axis) {
    float origin = originOf(node, axis);
    float step = gridStep(node.origin[axis] & 0xffu);
    bounds.min[axis] = gridPlane(origin, byteOf(lows[axis], k), step);
    bounds.max[axis] = gridPlane(origin, byteOf(highs[axis], k), step);
  }
  return bounds;
}

}  // namespace hdof
