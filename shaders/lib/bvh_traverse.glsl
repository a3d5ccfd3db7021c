// Closest-hit traversal of the scene BVH (binned SAH; each node holds both children's boxes), in
// the while-while form of Aila & Laine 2009, with a per-thread stack and an overflow guard. Needs
// lib/scene.glsl.
#ifndef HDOF_LIB_BVH_TRAVERSE_GLSL
#define HDOF_LIB_BVH_TRAVERSE_GLSL

// Nodes and triangles read as 16-byte texels of uniform texel buffers (four per node, three per
// triangle): one typed load each, through the texture cache on GPUs; lavapipe turns them into
// vector gathers, where it splits storage-buffer loads into a loop over the lanes.
layout(set = 0, binding = kBindingBvhNodes) uniform usamplerBuffer bvhNodeTexels;
layout(set = 0, binding = kBindingBvhTriangles) uniform usamplerBuffer bvhTriangleTexels;
#define bvhNodeRows(i) uintBitsToFloat(texelFetch(bvhNodeTexels, int(i)))
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

// Returns true on a hit closer than tMax. `overflowed` reports a full stack (subtrees skipped):
// the builder keeps the tree shallower than the stack, so this only guards against bad input.
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
  bool traversing = true;  // node is a pair still to visit
  while (true) {
    // Visit nodes until this lane has leaf triangles to test. The loop runs until every lane has
    // some (or is done), so the triangle loop below keeps the lanes busy together; hit leaves of
    // both children are tested in one loop.
    uint count0 = 0u, count1 = 0u, first0 = 0u, first1 = 0u;
    while (traversing && count0 + count1 == 0u) {
      vec4 min0 = bvhNodeRows(node * 4u), max0 = bvhNodeRows(node * 4u + 1u);
      vec4 min1 = bvhNodeRows(node * 4u + 2u), max1 = bvhNodeRows(node * 4u + 3u);
      float enter0 = intersectBox(origin, inverseDirection, min0.xyz, max0.xyz, hit.t);
      float enter1 = intersectBox(origin, inverseDirection, min1.xyz, max1.xyz, hit.t);
      uint link0 = floatBitsToUint(min0.w), link1 = floatBitsToUint(min1.w);
      bool leaf0 = (link0 & kBvhLeafBit) != 0u, leaf1 = (link1 & kBvhLeafBit) != 0u;
      count0 = leaf0 && enter0 < kNoEntry ? floatBitsToUint(max0.w) : 0u;
      count1 = leaf1 && enter1 < kNoEntry ? floatBitsToUint(max1.w) : 0u;
      first0 = link0 & ~kBvhLeafBit;
      first1 = link1 & ~kBvhLeafBit;
      bool visit0 = !leaf0 && enter0 < kNoEntry, visit1 = !leaf1 && enter1 < kNoEntry;
      if (visit0 && visit1) {
        bool swap = enter1 < enter0;
        if (stackSize < kBvhStackSize) {
          stackNodes[stackSize] = swap ? link0 : link1;
          stackEntries[stackSize] = swap ? enter0 : enter1;
          ++stackSize;
        } else {
          overflowed = true;
        }
        node = swap ? link1 : link0;
      } else if (visit0 || visit1) {
        node = visit0 ? link0 : link1;
      } else {
        traversing = false;
        while (stackSize > 0u && !traversing) {
          --stackSize;
          node = stackNodes[stackSize];
          traversing = stackEntries[stackSize] < hit.t;
        }
      }
    }
    if (count0 + count1 == 0u) break;
    for (uint i = 0u; i < count0 + count1; ++i)
      intersectTriangle(origin, direction, i < count0 ? first0 + i : first1 + (i - count0), hit);
  }
  return hit.triangle != 0xffffffffu;
}

#endif
