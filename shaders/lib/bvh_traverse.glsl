// Closest-hit traversal of the scene BVH (binned SAH, two children stored side by side), with a
// per-thread stack in shared memory and an overflow guard. Needs lib/scene.glsl and a workgroup
// of kTraceGroupSize threads.
#ifndef HDOF_LIB_BVH_TRAVERSE_GLSL
#define HDOF_LIB_BVH_TRAVERSE_GLSL

// Nodes and triangles read as aligned vec4 rows (two per node, three per triangle): one 16-byte
// load each, whatever the compiler makes of the scalar-layout structs.
layout(set = 0, binding = kBindingBvhNodes, std430) readonly buffer BvhNodeRows {
  vec4 bvhNodeRows[];
};
layout(set = 0, binding = kBindingBvhTriangles, std430) readonly buffer BvhTriangleRows {
  vec4 bvhTriangleRows[];
};

const uint kTraceGroupSize = 64;
// Stack entries interleaved by thread, so that neighbouring threads touch neighbouring words.


struct RayHit {
  float t;
  uint triangle;  // index buffer triangle number
  vec2 barycentrics;  // weights of vertices 1 and 2
};

// Entry distance of the ray into the box, or a huge value when it misses (or enters beyond tMax).
// The exit distance is widened a little so that rounding cannot lose a triangle lying in a face.
float intersectBox(vec3 origin, vec3 inverseDirection, vec3 boxMin, vec3 boxMax, float tMax) {
  vec3 t0 = (boxMin - origin) * inverseDirection;
  vec3 t1 = (boxMax - origin) * inverseDirection;
  vec3 tNear = min(t0, t1), tFar = max(t0, t1);
  float enter = max(max(tNear.x, tNear.y), max(tNear.z, 0.0));
  float leave = min(min(tFar.x, tFar.y), tFar.z) * 1.0000004;
  return enter <= min(leave, tMax) ? enter : 3.4e38;
}

// Möller–Trumbore; updates hit when the triangle is closer than hit.t.
void intersectTriangle(vec3 origin, vec3 direction, uint leafIndex, inout RayHit hit) {
  vec4 row0 = bvhTriangleRows[leafIndex * 3u];
  vec3 edge1 = bvhTriangleRows[leafIndex * 3u + 1u].xyz;
  vec3 edge2 = bvhTriangleRows[leafIndex * 3u + 2u].xyz;
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
  uint traversalStack[kBvhStackSize];
  uint stackSize = 0;
  uint node = 0;
  if (intersectBox(origin, inverseDirection, bvhNodeRows[0].xyz, bvhNodeRows[1].xyz, tMax) > 1e38)
    return false;
  while (true) {
    vec4 lo = bvhNodeRows[node * 2u];
    vec4 hi = bvhNodeRows[node * 2u + 1u];
    uint leftOrFirst = floatBitsToUint(lo.w);
    uint triangleCount = floatBitsToUint(hi.w);
    if (triangleCount > 0u) {
      for (uint i = 0u; i < triangleCount; ++i)
        intersectTriangle(origin, direction, leftOrFirst + i, hit);
    } else {
      uint left = leftOrFirst;
      float tA = intersectBox(origin, inverseDirection, bvhNodeRows[left * 2u].xyz,
                              bvhNodeRows[left * 2u + 1u].xyz, hit.t);
      float tB = intersectBox(origin, inverseDirection, bvhNodeRows[left * 2u + 2u].xyz,
                              bvhNodeRows[left * 2u + 3u].xyz, hit.t);
      uint near = left, far = left + 1u;
      if (tB < tA) {
        float swapT = tA;
        tA = tB;
        tB = swapT;
        near = left + 1u;
        far = left;
      }
      if (tA < 1e38) {
        if (tB < 1e38) {
          if (stackSize < kBvhStackSize)
            traversalStack[stackSize++] = far;
          else
            overflowed = true;
        }
        node = near;
        continue;
      }
    }
    if (stackSize == 0u) break;
    node = traversalStack[--stackSize];
  }
  return hit.triangle != 0xffffffffu;
}

#endif
