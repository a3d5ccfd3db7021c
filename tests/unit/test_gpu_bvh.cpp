#include "scene/gpu_bvh.h"

#include <gtest/gtest.h>

#include <functional>
#include <random>

namespace hdof {
namespace {

const std::string kLivingRoom =
    std::string(HDOF_ASSETS_DIR) + "/scenes/living-room/living-room.gltf";

bool contains(const Aabb& outer, const Aabb& inner) {
  return glm::all(glm::lessThanEqual(outer.min, inner.min)) &&
         glm::all(glm::greaterThanEqual(outer.max, inner.max));
}

Aabb triangleBounds(const Scene& scene, const gpu::BvhTriangle& triangle) {
  Aabb bounds;
  for (int corner = 0; corner < 3; ++corner)
    bounds.grow(scene.vertices[scene.indices[3 * triangle.index + corner]].position);
  return bounds;
}

// Walks the packed tree: every node is reached once, every packed triangle lies in exactly one
// leaf, the packed triangles are the built tree's, and each child's decoded box holds every
// triangle beneath it, exactly (the grid rounds outwards), and exceeds their bounds by at most two
// grid steps per plane.
void expectSameTreeInBoxesThatOnlyGrow(const Scene& scene, const Bvh& bvh,
                                       const PackedBvh& packed) {
  const std::vector<gpu::BvhWideNode>& wide = packed.nodes;
  ASSERT_EQ(packed.triangles.size(), bvh.triangles.size());
  std::vector<int> packedTimes(scene.triangleCount(), 0), builtTimes(scene.triangleCount(), 0);
  for (const gpu::BvhTriangle& t : packed.triangles) ++packedTimes.at(t.index);
  for (const gpu::BvhTriangle& t : bvh.triangles) ++builtTimes.at(t.index);
  ASSERT_EQ(packedTimes, builtTimes);
  std::vector<int> visits(wide.size(), 0), slots(packed.triangles.size(), 0);
  std::function<Aabb(uint32_t)> walk = [&](uint32_t index) {
    Aabb all;
    if (index >= wide.size()) {
      ADD_FAILURE() << "link " << index << " past the last node";
      return all;
    }
    ++visits[index];
    const gpu::BvhWideNode& node = wide[index];
    for (uint32_t k = 0; k < gpu::kBvhWidth; ++k) {
      uint32_t info = wideChildInfo(node, k);
      if (info == gpu::kBvhEmptyChild) continue;
      Aabb beneath;
      uint32_t link = wideChildLink(node, k);
      if (info == gpu::kBvhInteriorChild) {
        beneath = walk(link);
      } else {
        EXPECT_LE(size_t{link} + info, packed.triangles.size());
        for (uint32_t slot = link; slot < link + info; ++slot) {
          ++slots.at(slot);
          beneath.grow(triangleBounds(scene, packed.triangles[slot]));
        }
      }
      Aabb box = wideChildBounds(node, k);
      EXPECT_TRUE(contains(box, beneath)) << "node " << index << " child " << k;
      for (int axis = 0; axis < 3; ++axis) {
        float step = std::ldexp(1.0f, int(node.origin[axis] & 0xffu) - 127);
        EXPECT_GE(box.min[axis], beneath.min[axis] - 2.0f * step);
        EXPECT_LE(box.max[axis], beneath.max[axis] + 2.0f * step);
      }
      all.grow(beneath);
    }
    return all;
  };
  walk(0);
  for (size_t i = 0; i < visits.size(); ++i) ASSERT_EQ(visits[i], 1) << "node " << i;
  for (size_t i = 0; i < slots.size(); ++i) ASSERT_EQ(slots[i], 1) << "slot " << i;
}

TEST(GpuBvh, WideNodesHoldTheSameTreeInBoxesThatOnlyGrow) {
  Scene dof = makeBuiltinScene("dof");
  for (BvhBuildOptions options : {BvhBuildOptions{}, BvhBuildOptions{4, 1}}) {
    Bvh bvh = buildBvh(dof.vertices, dof.indices, options);
    ASSERT_GT(bvh.nodes.size(), 1u);
    expectSameTreeInBoxesThatOnlyGrow(dof, bvh, packBvh(bvh));
  }
  Scene room = loadScene(kLivingRoom);
  Bvh bvh = buildBvh(room.vertices, room.indices);
  PackedBvh packed = packBvh(bvh);
  expectSameTreeInBoxesThatOnlyGrow(room, bvh, packed);
  // Collapsed: a binary tree of n interior nodes becomes at most about n / 3 wide ones.
  size_t interior = (bvh.nodes.size() - 1) / 2;
  EXPECT_LT(packed.nodes.size(), interior / 2);
}

// The shader's traversal, reduced to its pruning: from the root, only children whose decoded box
// the ray enters by the closest hit. The leaf holding the closest hit (found in the built
// tree) must be among the leaves reached, for rays from everywhere in every direction.
TEST(GpuBvh, ATraversalOfWideNodesReachesTheClosestHit) {
  for (const Scene& scene : {makeBuiltinScene("dof"), loadScene(kLivingRoom)}) {
    Bvh bvh = buildBvh(scene.vertices, scene.indices);
    PackedBvh packed = packBvh(bvh);
    const std::vector<gpu::BvhWideNode>& wide = packed.nodes;
    std::vector<uint32_t> slotOf(scene.triangleCount());
    for (uint32_t slot = 0; slot < packed.triangles.size(); ++slot)
      slotOf[packed.triangles[slot].index] = slot;
    std::mt19937 random(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::normal_distribution<float> gaussian;
    glm::vec3 low = scene.bounds.min, span = scene.bounds.extent();
    int hits = 0;
    for (int ray = 0; ray < 2000; ++ray) {
      glm::vec3 origin = low + span * glm::vec3(unit(random), unit(random), unit(random));
      glm::vec3 direction(gaussian(random), gaussian(random), gaussian(random));
      std::optional<RayHit> closest = intersect(bvh, origin, direction);
      if (!closest) continue;
      ++hits;
      uint32_t target = slotOf[closest->triangle];
      // Until the hit is found the traversal's reach is longer; a little past it covers rounding
      // where the triangle lies in a face of its box.
      float reach = closest->t * 1.00001f;
      glm::vec3 inverse = safeInverse(direction);
      bool reached = false;
      std::vector<uint32_t> stack{0};
      while (!stack.empty() && !reached) {
        const gpu::BvhWideNode& node = wide[stack.back()];
        stack.pop_back();
        for (uint32_t k = 0; k < gpu::kBvhWidth; ++k) {
          uint32_t info = wideChildInfo(node, k);
          if (info == gpu::kBvhEmptyChild ||
              std::isinf(enterBox(wideChildBounds(node, k), origin, inverse, 0.0f, reach)))
            continue;
          uint32_t link = wideChildLink(node, k);
          if (info == gpu::kBvhInteriorChild)
            stack.push_back(link);
          else
            reached |= target >= link && target < link + info;
        }
      }
      ASSERT_TRUE(reached) << scene.name << " ray " << ray;
    }
    EXPECT_GT(hits, 500) << scene.name;
  }
}

TEST(GpuBvh, ALeafRootIsTheOnlyChildOfNodeZero) {
  std::vector<gpu::Vertex> vertices(3);
  vertices[1].position = {1, 0, 0};
  vertices[2].position = {0, 1, 0};
  std::vector<gpu::BvhWideNode> wide = packBvh(buildBvh(vertices, {0, 1, 2})).nodes;
  ASSERT_EQ(wide.size(), 1u);
  EXPECT_EQ(wideChildInfo(wide[0], 0), 1u);
  EXPECT_EQ(wideChildLink(wide[0], 0), 0u);
  EXPECT_TRUE(contains(wideChildBounds(wide[0], 0), Aabb{{0, 0, 0}, {1, 1, 0}}));
  for (uint32_t k = 1; k < gpu::kBvhWidth; ++k)
    EXPECT_EQ(wideChildInfo(wide[0], k), gpu::kBvhEmptyChild);

  std::vector<gpu::BvhWideNode> empty = packBvh(buildBvh({}, {})).nodes;
  ASSERT_EQ(empty.size(), 1u);
  for (uint32_t k = 0; k < gpu::kBvhWidth; ++k)
    EXPECT_EQ(wideChildInfo(empty[0], k), gpu::kBvhEmptyChild);
}

}  // namespace
}  // namespace hdof
