// Closest-hit traversal of the scene BVH (binned SAH, collapsed into nodes of four children with
// quantised boxes), in the while-while form of Aila & Laine 2009: interior children are visited
// nearest first, the hit leaves of a node tested together; the siblings left to visit are kept in
// groups, the newest in registers and the others on a per-thread stack with an overflow guard.
// Needs lib/scene.glsl.
#ifndef HDOF_LIB_BVH_TRAVERSE_GLSL
#define HDOF_LIB_BVH_TRAVERSE_GLSL
#include "lib/skippable.glsl"

// Nodes and triangles read as 16-byte texels of uniform texel buffers (three each): one typed
// load each, through the texture cache on GPUs; lavapipe turns them into vector gathers, where it
// splits storage-buffer loads into a loop over the lanes.
layout(set = 0, binding = kBindingBvhNodes) uniform usamplerBuffer bvhNodeTexels;
layout(set = 0, binding = kBindingBvhTriangles) uniform usamplerBuffer bvhTriangleTexels;
#define bvhTriangleRows(i) uintBitsToFloat(texelFetch(bvhTriangleTexels, int(i)))

struct RayHit {
  float t;
  uint triangle;  // index buffer triangle number
  vec2 barycentrics;  // weights of vertices 1 and 2
};

const float kNoEntry = 1.0 / 0.0;  // +infinity: beyond any hit

// Möller–Trumbore; updates hit when the triangle lies between tMin and hit.t.
void intersectTriangle(vec3 origin, vec3 direction, float tMin, uint leafIndex,
                       inout RayHit hit) {
  vec4 row0 = bvhTriangleRows(leafIndex * 3u);
  vec3 edge1 = bvhTriangleRows(leafIndex * 3u + 1u).xyz;
  vec3 edge2 = bvhTriangleRows(leafIndex * 3u + 2u).xyz;
  vec3 p = cross(direction, edge2);
  float det = dot(edge1, p);
  if (abs(det) < 1e-12) return;
  float inverseDet = 1.0 / det;
  vec3 toOrigin = origin - row0.xyz;
  float u = dot(toOrigin, p) * inverseDet;
  if (u < 0.0 || u > 1.0) return;
  vec3 q = cross(toOrigin, edge1);
  float v = dot(direction, q) * inverseDet;
  if (v < 0.0 || u + v > 1.0) return;
  float t = dot(edge2, q) * inverseDet;
  if (t > tMin && t < hit.t) {
    hit.t = t;
    hit.triangle = floatBitsToUint(row0.w);
    hit.barycentrics = vec2(u, v);
  }
}

// Orders two children by entry distance.
void sortChildren(inout float entryA, inout uint rankA, inout float entryB, inout uint rankB) {
  if (entryB < entryA) {
    float entry = entryA;
    entryA = entryB;
    entryB = entry;
    uint rank = rankA;
    rankA = rankB;
    rankB = rank;
  }
}

// Entry distances into a node's four child boxes (from tMin), kNoEntry where the ray misses one,
// leaves it before tMin, enters it beyond tMax, or the child is empty. Along each axis the ray
// enters a box through the plane it meets first (the low one for a positive direction) and
// leaves through the other; a plane's distance is q * planeStep + planeZero for its quantised
// position q, one multiply-add. Each axis's slab is widened by the rounding error that this can
// reach on that axis, so that rounding cannot lose a triangle lying in a face. The entry is the
// largest of the three entering distances and tMin, the exit the smallest of the leaving ones and
// tMax, both taken on the floats' bits as signed integers: non-negative floats order as their
// bits do and every negative one below them, so the entry (at least tMin >= 0) is exact, and an
// exit below zero stays below zero, which rejects the box as the true exit would. A float min or
// max is three instructions on a CPU device (a NaN check and a blend after it), an integer one is
// one: the closeup's selective trace 101.3 -> 91.6 ms on one thread, images unchanged.
vec4 enterChildren(uvec4 row0, uvec4 row1, uvec4 row2, uvec4 info, vec3 origin,
                   vec3 inverseDirection, float tMin, float tMax) {
  vec3 gridOrigin = uintBitsToFloat(row0.xyz & ~0xffu);
  vec3 gridStep = uintBitsToFloat((row0.xyz & 0xffu) << 23u);
  vec3 planeStep = gridStep * inverseDirection;
  vec3 planeZero = (gridOrigin - origin) * inverseDirection;
  // On an axis the ray runs along (inverseDirection 1e20) the slack is as huge as the distances
  // and leaves them on the same side of the box.
  vec3 slack = 1e-6 * (abs(planeZero) + 255.0 * abs(planeStep));
  vec3 enterZero = planeZero - slack, leaveZero = planeZero + slack;
  uvec3 lows = row1.xyz, highs = uvec3(row1.w, row2.xy);
  bvec3 positive = greaterThan(inverseDirection, vec3(0.0));
  uvec3 enterPlanes = mix(highs, lows, positive), leavePlanes = mix(lows, highs, positive);
  vec4 entries;
  for (uint k = 0u; k < kBvhWidth; ++k) {
    uint shift = 8u * k;
    vec3 tEnter = vec3((enterPlanes >> shift) & 0xffu) * planeStep + enterZero;
    vec3 tLeave = vec3((leavePlanes >> shift) & 0xffu) * planeStep + leaveZero;
    ivec3 enterBits = floatBitsToInt(tEnter), leaveBits = floatBitsToInt(tLeave);
    float enter = intBitsToFloat(
        max(max(enterBits.x, enterBits.y), max(enterBits.z, floatBitsToInt(tMin))));
    float leave = intBitsToFloat(
        min(min(leaveBits.x, leaveBits.y), min(leaveBits.z, floatBitsToInt(tMax))));
    entries[k] = info[k] != kBvhEmptyChild && enter <= leave ? enter : kNoEntry;
  }
  return entries;
}

// Returns true on a hit between tMin (>= 0) and tMax. `overflowed` reports a full stack (subtrees
// skipped): trees of sane input stay well inside it, so this only guards against bad input.
bool traceClosest(vec3 origin, vec3 direction, float tMin, float tMax, out RayHit hit,
                  out bool overflowed) {
  hit.t = tMax;
  hit.triangle = 0xffffffffu;
  hit.barycentrics = vec2(0.0);
  overflowed = false;
  vec3 inverseDirection = 1.0 / max(abs(direction), vec3(1e-20)) * sign(direction);
  inverseDirection = mix(inverseDirection, vec3(1e20), equal(direction, vec3(0.0)));
  // Siblings still to visit, in groups: the interior children of one node that the ray enters,
  // but the nearest, nearest first. The newest group lives in registers, with each child's entry
  // distance; older ones wait on the stack, with their nearest child's (a node's visit stores at
  // most one group, where a stack of nodes stored each child: lavapipe scatters a store to a
  // local array lane by lane). A group is the node's first interior child (kBvhMaxNodes) << 8 and
  // the children's ranks among its interior children, two bits each from bit 0; on the stack,
  // their count in bits 6-7. Local arrays: shared memory measured slower here (lavapipe), and
  // callers keep any group size.
  uint stackGroups[kBvhStackSize];
  float stackEntries[kBvhStackSize];
  uint stackSize = 0u;
  uint group = 0u;
  uint groupCount = 0u;
  vec3 groupEntries = vec3(kNoEntry);
  uint node = 0u;
  bool traversing = true;  // node is an interior node still to visit
  while (true) {
    // Visit nodes until this lane has leaf triangles to test. The loop runs until every lane has
    // some (or is done), so the triangle loop below keeps the lanes busy together.
    uvec4 leafFirst = uvec4(0u), leafCount = uvec4(0u);
    while (traversing && leafCount == uvec4(0u)) {
      uvec4 row0 = texelFetch(bvhNodeTexels, int(node * 3u));
      uvec4 row1 = texelFetch(bvhNodeTexels, int(node * 3u + 1u));
      uvec4 row2 = texelFetch(bvhNodeTexels, int(node * 3u + 2u));
      uvec4 info = (uvec4(row2.z) >> uvec4(0u, 8u, 16u, 24u)) & 0xffu;
      vec4 entries = enterChildren(row0, row1, row2, info, origin, inverseDirection, tMin, hit.t);
      // Links: interior children are consecutive nodes from the first (their rank among the
      // interior children), leaves' triangles consecutive from the first triangle, both in child
      // order.
      bvec4 interior = equal(info, uvec4(kBvhInteriorChild));
      uvec4 sizes = mix(mix(info, uvec4(0u), equal(info, uvec4(kBvhEmptyChild))), uvec4(1u),
                        interior);
      uvec4 before = uvec4(0u, sizes.x, sizes.x + sizes.y, sizes.x + sizes.y + sizes.z);
      uvec4 ranks = uvec4(0u, uint(interior.x), uint(interior.x) + uint(interior.y),
                          uint(interior.x) + uint(interior.y) + uint(interior.z));
      bvec4 leaves = notEqual(info, uvec4(kBvhInteriorChild));
      vec4 leafEntries = mix(entries, vec4(kNoEntry), not(leaves));
      leafCount = mix(uvec4(0u), info, lessThan(leafEntries, vec4(kNoEntry)));
      leafFirst = row2.w + before - ranks;
      // Interior children hit, nearest first (a sorting network over four).
      vec4 inner = mix(entries, vec4(kNoEntry), leaves);
      float e0 = inner.x, e1 = inner.y, e2 = inner.z, e3 = inner.w;
      uint r0 = ranks.x, r1 = ranks.y, r2 = ranks.z, r3 = ranks.w;
      sortChildren(e0, r0, e1, r1);
      sortChildren(e2, r2, e3, r3);
      sortChildren(e0, r0, e2, r2);
      sortChildren(e1, r1, e3, r3);
      sortChildren(e1, r1, e2, r2);
      if (e0 < kNoEntry) {
        uint others = uint(e1 < kNoEntry) + uint(e2 < kNoEntry) + uint(e3 < kNoEntry);
        if (others > 0u) {
          // The nearest goes next; the others become the newest group, the last one stored
          // (most visits store nothing).
          SKIPPABLE_IF(groupCount > 0u) {
            if (stackSize < kBvhStackSize) {
              stackGroups[stackSize] = group | (groupCount << 6u);
              stackEntries[stackSize] = groupEntries.x;
              ++stackSize;
            } else {
              overflowed = true;
            }
          }
          group = (row0.w << 8u) | r1 | (r2 << 2u) | (r3 << 4u);
          groupCount = others;
          groupEntries = vec3(e1, e2, e3);
        }
        node = row0.w + r0;
      } else {
        // The next child nearer than the hit: from the newest group while it lasts, then from
        // the stack's groups, each loaded only when the one before is spent.
        traversing = false;
        while (true) {
          while (!traversing && groupCount > 0u) {
            node = (group >> 8u) + (group & 3u);
            traversing = groupEntries.x < hit.t;
            group = (group & ~0xffu) | ((group & 0x3cu) >> 2u);
            groupEntries = groupEntries.yzx;
            --groupCount;
          }
          if (traversing || stackSize == 0u) break;
          --stackSize;
          group = stackGroups[stackSize];
          groupCount = (group >> 6u) & 3u;
          groupEntries = vec3(stackEntries[stackSize]);
        }
      }
    }
    uint total = leafCount.x + leafCount.y + leafCount.z + leafCount.w;
    if (total == 0u) break;
    // The hit leaves' triangles, one after the other.
    uvec4 ends = leafCount;
    ends.y += ends.x;
    ends.z += ends.y;
    ends.w += ends.z;
    for (uint i = 0u; i < total; ++i) {
      uint leaf = i < ends.x ? 0u : i < ends.y ? 1u : i < ends.z ? 2u : 3u;
      intersectTriangle(origin, direction, tMin,
                        leafFirst[leaf] + i - (ends[leaf] - leafCount[leaf]), hit);
    }
  }
  return hit.triangle != 0xffffffffu;
}

#endif
