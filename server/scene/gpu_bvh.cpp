#include "scene/gpu_bvh.h"

namespace hdof {
namespace {

class PairNodePacker {
 public:
  explicit PairNodePacker(const Bvh& bvh) : nodes_(bvh.nodes) {
    pairs_.reserve(nodes_.size() / 2 + 1);
  }

  std::vector<gpu::BvhPairNode> pack() && {
    const gpu::BvhNode& root = nodes_.at(0);
    if (nodes_.size() > 1) {
      packChildrenOf(root);
    } else {  // the root is a leaf (of no triangles when the tree is empty)
      gpu::BvhChild empty = leaf(root);
      empty.triangleCount = 0;
      pairs_.push_back({leaf(root), empty});
    }
    return std::move(pairs_);
  }

 private:
  static gpu::BvhChild leaf(const gpu::BvhNode& node) {
    return {node.boundsMin, gpu::kBvhLeafBit | node.leftOrFirst, node.boundsMax,
            node.triangleCount};
  }

  // Appends the node holding an interior node's children, then their subtrees depth first, so
  // that the first child's node follows its parent's; returns its index.
  uint32_t packChildrenOf(const gpu::BvhNode& node) {
    auto index = static_cast<uint32_t>(pairs_.size());
    pairs_.emplace_back();
    gpu::BvhPairNode pair;
    for (uint32_t k = 0; k < 2; ++k) {
      const gpu::BvhNode& child = nodes_.at(node.leftOrFirst + k);
      pair.children[k] =
          child.triangleCount > 0
              ? leaf(child)
              : gpu::BvhChild{child.boundsMin, packChildrenOf(child), child.boundsMax, 0u};
    }
    pairs_[index] = pair;  // after the recursion, which may have moved pairs_
    return index;
  }

  const std::vector<gpu::BvhNode>& nodes_;
  std::vector<gpu::BvhPairNode> pairs_;
};

}  // namespace

std::vector<gpu::BvhPairNode> packBvhPairNodes(const Bvh& bvh) {
  return PairNodePacker(bvh).pack();
}

}  // namespace hdof
