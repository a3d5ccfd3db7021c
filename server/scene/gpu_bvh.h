// The BVH in the layout the compute shaders traverse (gpu::BvhWideNode in shared/scene_data.h):
// the built binary tree collapsed into nodes of up to four children, whose boxes are quantised to
// 8 bits per plane, so that three 16-byte fetches test four boxes.
#pragma once

#include "scene/bvh.h"

#include <vector>

namespace hdof {

// Wide nodes, each node's interior children consecutive, and the triangles in the order of the
// wide nodes' leaves (each node's leaves' triangles consecutive). Node 0 holds the root's
// children; a tree that is one leaf becomes a node with that leaf as its only child (none when it
// has no triangles).
struct PackedBvh {
  std::vector<gpu::BvhWideNode> nodes;
  std::vector<gpu::BvhTriangle> triangles;
};
PackedBvh packBvh(const Bvh& bvh);

// Child k of a packed node as the traversal reads it: its kind (gpu::kBvhInteriorChild,
// gpu::kBvhEmptyChild or a leaf's triangle count), its link (the interior child's node, or the
// leaf's first triangle in PackedBvh::triangles), and its box decoded from the grid, which holds
// the built tree's box.
uint32_t wideChildInfo(const gpu::BvhWideNode& node, uint32_t k);
uint32_t wideChildLink(const gpu::BvhWideNode& node, uint32_t k);
Aabb wideChildBounds(const gpu::BvhWideNode& node, uint32_t k);

}  // namespace hdof
