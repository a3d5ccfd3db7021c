#include "scene/gpu_bvh.h"

#include <gtest/gtest.h>

namespace hdof {
namespace {

// Walks the built tree and the packed one together: every interior node's children reappear, box
// and leaf range unchanged, in exactly one packed node, and nothing else is packed.
void expectSameTree(const Bvh& bvh, const std::vector<gpu::BvhPairNode>& pairs) {
  std::vector<int> visits(pairs.size(), 0);
  struct Visit {
    uint32_t node, pair;
  };
  std::vector<Visit> stack{{0, 0}};
  while (!stack.empty()) {
    Visit visit = stack.back();
    stack.pop_back();
    ASSERT_LT(visit.pair, pairs.size());
    ++visits[visit.pair];
    for (uint32_t k = 0; k < 2; ++k) {
      const gpu::BvhNode& node = bvh.nodes.at(bvh.nodes[visit.node].leftOrFirst + k);
      const gpu::BvhChild& child = pairs[visit.pair].children[k];
      EXPECT_EQ(child.boundsMin, node.boundsMin);
      EXPECT_EQ(child.boundsMax, node.boundsMax);
      EXPECT_EQ(child.triangleCount, node.triangleCount);
      if (node.triangleCount > 0)
        EXPECT_EQ(child.link, gpu::kBvhLeafBit | node.leftOrFirst);
      else
        stack.push_back({bvh.nodes[visit.node].leftOrFirst + k, child.link});
    }
  }
  for (size_t i = 0; i < visits.size(); ++i) EXPECT_EQ(visits[i], 1) << "node " << i;
  EXPECT_EQ(pairs.size(), (bvh.nodes.size() - 1) / 2);
}

TEST(GpuBvh, PairNodesHoldTheSameTree) {
  Scene scene = makeBuiltinScene("dof");
  for (BvhBuildOptions options : {BvhBuildOptions{}, BvhBuildOptions{4, 1}}) {
    Bvh bvh = buildBvh(scene.vertices, scene.indices, options);
    ASSERT_GT(bvh.nodes.size(), 1u);
    std::vector<gpu::BvhPairNode> pairs = packBvhPairNodes(bvh);
    expectSameTree(bvh, pairs);
    // Depth first: the first interior child's node comes right after its parent's.
    const gpu::BvhChild& first = pairs[0].children[0];
    if (first.triangleCount == 0) {
      EXPECT_EQ(first.link, 1u);
    }
  }
}

TEST(GpuBvh, ALeafRootGetsAnEmptySibling) {
  std::vector<gpu::Vertex> vertices(3);
  vertices[1].position = {1, 0, 0};
  vertices[2].position = {0, 1, 0};
  std::vector<gpu::BvhPairNode> pairs = packBvhPairNodes(buildBvh(vertices, {0, 1, 2}));
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].children[0].link, gpu::kBvhLeafBit);
  EXPECT_EQ(pairs[0].children[0].triangleCount, 1u);
  EXPECT_EQ(pairs[0].children[1].triangleCount, 0u);
  EXPECT_NE(pairs[0].children[1].link & gpu::kBvhLeafBit, 0u);

  std::vector<gpu::BvhPairNode> empty = packBvhPairNodes(buildBvh({}, {}));
  ASSERT_EQ(empty.size(), 1u);
  EXPECT_EQ(empty[0].children[0].triangleCount + empty[0].children[1].triangleCount, 0u);
}

}  // namespace
}  // namespace hdof
