// The BVH in the layout the compute shaders traverse (gpu::BvhPairNode in shared/scene_data.h):
// the built tree's nodes regrouped so that each GPU node holds the boxes of both children of one
// interior node, and a single fetch tests both.
#pragma once

#include "scene/bvh.h"

#include <vector>

namespace hdof {

// Node 0 holds the root's children; a tree that is one leaf becomes a node whose second child is
// an empty leaf. Leaves keep their triangle ranges in bvh.triangles.
std::vector<gpu::BvhPairNode> packBvhPairNodes(const Bvh& bvh);

}  // namespace hdof
