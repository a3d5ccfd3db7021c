// Closest-hit traversal of the scene BVH (binned SAH, collapsed into nodes of four children with
// quantised boxes), in the while-while form of Aila & Laine 2009: interior children are visited
// nearest first, the hit leaves of a node tested together, with a per-thread stack and an overflow
// guard. Needs lib/scene.glsl.
#ifndef HDOF_LIB_BVH_TRAVERSE_GLSL
#define HDOF_LIB_BVH_TRAVERSE_GLSL

// Nodes and triangles read as 16-byte texels of uniform texel buffers (three each): one typed load each, through the texture cache on GPUs; lavapipe turns them into
// vector gathers, where it splits storage-buffer loads into a loop over the lanes.
layout(set = 0, binding = kBindingBvhNodes) uniform usamplerBuffer bvhNodeTexels;
layout(set = 0, binding = kBindingBvhTriangles) uniform usamplerBuffer bvhTriangleTexels;
#define bvhTriangleRows(i) uintBitsToFloat(texelFetch(bvhTriangleTexels, int(i)))

struct RayHit {
  float t;
  uint triangle;  // index buffer triangle number
  vec2 barycentrics;  // weights of vertices 1 and 2
};

const float kNoEntry = 1.0 / 0.0;  // +infinity: beyond any hit

// Entry distance of the ray into the box, or kNoEntry when it misses (or enters beyond tMax).
// The exit distance is widened a little so that rounding cannot lose a triangle lying in a face.
float intersectBox(vec3 origin, vec3 inverseDirection, vec3 boxMin, vec3 boxMax, float tMax) {
  vec3 t0 = (boxMin - origin) * inverseDirection;
  vec3 t1 = (boxMax - origin) * inverseDirection;
  vec3 tNear = min(t0, t1), tFar = max(t0, t1);
  float enter = max(max(tNear.x, tNear.y), max(tNear.z, 0.0));
  float leave = min(min(tFar.x, tFar.y), tFar.z) * 1.0000004;
  return enter <= min(leave, tMax) ? enter : kNoEntry;
}

// Möller–Trumbore; updates hit when the triangle is closer than hit.t.
void intersectTriangle(vec3 origin, vec3 direction, uint leafIndex, inout RayHit hit) {
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
  if (t > 0.0 && t < hit.t) {
    hit.t = t;
    hit.triangle = floatBitsToUint(row0.w);
    hit.barycentrics = vec2(u, v);
  }
}

// Orders two children by entry distance.
void sortChildren(inout float entryA, inout uint linkA, inout float entryB, inout uint linkB) {
  if (entryB < entryA) {
    float entry = entryA;
    entryA = entryB;
    entryB = entry;
    uint link = linkA;
    linkA = linkB;
    linkB = link;
  }
}

// Returns true on a hit closer than tMax. `overflowed` reports a full stack (subtrees skipped):
// trees of sane input stay well inside it, so this only guards against bad input.
bool traceClosest(vec3 origin, vec3 direction, float tMax, out RayHit hit, out bool overflowed) {
  hit.t = tMax;
  hit.triangle = 0xffffffffu;
  hit.barycentrics = vec2(0.0);
  overflowed = false;
  vec3 inverseDirection = 1.0 / max(abs(direction), vec3(1e-20)) * sign(direction);
  inverseDirection = mix(inverseDirection, vec3(1e20), equal(direction, vec3(0.0)));
  // Pushed subtrees with their entry distances, so that a pop can skip those behind the hit. A
  // local array: shared memory measured slower here (lavapipe), and callers keep any group size.
  uint stackNodes[kBvhStackSize];
  float stackEntries[kBvhStackSize];
  uint stackSize = 0u;
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
      vec3 gridOrigin = uintBitsToFloat(row0.xyz & ~0xffu);
      vec3 gridStep = uintBitsToFloat((row0.xyz & 0xffu) << 23u);
      uvec3 lows = row1.xyz, highs = uvec3(row1.w, row2.xy);
      uvec4 info = (uvec4(row2.z) >> uvec4(0u, 8u, 16u, 24u)) & 0xffu;
      // Links: interior children are consecutive nodes from the first, leaves' triangles
      // consecutive from the first triangle, both in child order.
      bvec4 interior = equal(info, uvec4(kBvhInteriorChild));
      uvec4 sizes = mix(mix(info, uvec4(0u), equal(info, uvec4(kBvhEmptyChild))), uvec4(1u),
                        interior);
      uvec4 before = uvec4(0u, sizes.x, sizes.x + sizes.y, sizes.x + sizes.y + sizes.z);
      uvec4 interiorBefore = uvec4(0u, uint(interior.x), uint(interior.x) + uint(interior.y),
                                   uint(interior.x) + uint(interior.y) + uint(interior.z));
      uvec4 links = mix(row2.w + before - interiorBefore, row0.w + interiorBefore, interior);
      vec4 entries;
      for (uint k = 0u; k < kBvhWidth; ++k) {
        uint shift = 8u * k;
        vec3 boxMin = gridOrigin + vec3((lows >> shift) & 0xffu) * gridStep;
        vec3 boxMax = gridOrigin + vec3((highs >> shift) & 0xffu) * gridStep;
        entries[k] = info[k] == kBvhEmptyChild
                         ? kNoEntry
                         : intersectBox(origin, inverseDirection, boxMin, boxMax, hit.t);
      }
      bvec4 leaves = notEqual(info, uvec4(kBvhInteriorChild));
      vec4 leafEntries = mix(entries, vec4(kNoEntry), not(leaves));
      leafCount = mix(uvec4(0u), info, lessThan(leafEntries, vec4(kNoEntry)));
      leafFirst = links;
      // Interior children hit, nearest first (a sorting network over four).
      vec4 inner = mix(entries, vec4(kNoEntry), leaves);
      float e0 = inner.x, e1 = inner.y, e2 = inner.z, e3 = inner.w;
      uint l0 = links.x, l1 = links.y, l2 = links.z, l3 = links.w;
      sortChildren(e0, l0, e1, l1);
      sortChildren(e2, l2, e3, l3);
      sortChildren(e0, l0, e2, l2);
      sortChildren(e1, l1, e3, l3);
      sortChildren(e1, l1, e2, l2);
      if (e0 < kNoEntry) {
        // Push the others farthest first, so that the nearer pop first.
        uint pushes = uint(e1 < kNoEntry) + uint(e2 < kNoEntry) + uint(e3 < kNoEntry);
        if (stackSize + pushes > kBvhStackSize) overflowed = true;
        if (e3 < kNoEntry && stackSize < kBvhStackSize) {
          stackNodes[stackSize] = l3;
          stackEntries[stackSize] = e3;
          ++stackSize;
        }
        if (e2 < kNoEntry && stackSize < kBvhStackSize) {
          stackNodes[stackSize] = l2;
          stackEntries[stackSize] = e2;
          ++stackSize;
        }
        if (e1 < kNoEntry && stackSize < kBvhStackSize) {
          stackNodes[stackSize] = l1;
          stackEntries[stackSize] = e1;
          ++stackSize;
        }
        node = l0;
      } else {
        traversing = false;
        while (stackSize > 0u && !traversing) {
          --stackSize;
          node = stackNodes[stackSize];
          traversing = stackEntries[stackSize] < hit.t;
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
      intersectTriangle(origin, direction, leafFirst[leaf] + i - (ends[leaf] - leafCount[leaf]),
                        hit);
    }
  }
  return hit.triangle != 0xffffffffu;
}

#endif
