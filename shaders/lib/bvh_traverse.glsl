// Closest-hit traversal of the scene BVH (binned SAH, two children stored side by side), with a
// per-thread stack and an overflow guard. Needs lib/scene.glsl.
#ifndef HDOF_LIB_BVH_TRAVERSE_GLSL
#define HDOF_LIB_BVH_TRAVERSE_GLSL

struct RayHit {
  float t;
  uint triangle;  // index buffer triangle number
  vec2 barycentrics;  // weights of vertices 1 and 2
};

// Entry distance of the ray into the box, or a huge value when it misses (or enters beyond tMax).
float intersectBox(vec3 origin, vec3 inverseDirection, vec3 boxMin, vec3 boxMax, float tMax) {
  vec3 t0 = (boxMin - origin) * inverseDirection;
  vec3 t1 = (boxMax - origin) * inverseDirection;
  vec3 tNear = min(t0, t1), tFar = max(t0, t1);
  float enter = max(max(tNear.x, tNear.y), max(tNear.z, 0.0));
  float leave = min(min(tFar.x, tFar.y), min(tFar.z, tMax));
  return enter <= leave ? enter : 3.4e38;
}

// Möller–Trumbore; updates hit when the triangle is closer than hit.t.
void intersectTriangle(vec3 origin, vec3 direction, uint leafIndex, inout RayHit hit) {
  BvhTriangle tri = bvhTriangles[leafIndex];
  vec3 p = cross(direction, tri.edge2);
  float det = dot(tri.edge1, p);
  if (abs(det) < 1e-12) return;
  float inverseDet = 1.0 / det;
  vec3 toOrigin = origin - tri.v0;
  float u = dot(toOrigin, p) * inverseDet;
  if (u < 0.0 || u > 1.0) return;
  vec3 q = cross(toOrigin, tri.edge1);
  float v = dot(direction, q) * inverseDet;
  if (v < 0.0 || u + v > 1.0) return;
  float t = dot(tri.edge2, q) * inverseDet;
  if (t > 0.0 && t < hit.t) {
    hit.t = t;
    hit.triangle = tri.index;
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
  uint stack[kBvhStackSize];
  uint stackSize = 0;
  uint node = 0;
  if (intersectBox(origin, inverseDirection, bvhNodes[0].boundsMin, bvhNodes[0].boundsMax, tMax) >
      1e38)
    return false;
  while (true) {
    BvhNode current = bvhNodes[node];
    if (current.triangleCount > 0) {
      for (uint i = 0; i < current.triangleCount; ++i)
        intersectTriangle(origin, direction, current.leftOrFirst + i, hit);
    } else {
      uint left = current.leftOrFirst;
      BvhNode a = bvhNodes[left];
      BvhNode b = bvhNodes[left + 1];
      float tA = intersectBox(origin, inverseDirection, a.boundsMin, a.boundsMax, hit.t);
      float tB = intersectBox(origin, inverseDirection, b.boundsMin, b.boundsMax, hit.t);
      uint near = left, far = left + 1;
      if (tB < tA) {
        float swapT = tA;
        tA = tB;
        tB = swapT;
        near = left + 1;
        far = left;
      }
      if (tA < 1e38) {
        if (tB < 1e38) {
          if (stackSize < kBvhStackSize)
            stack[stackSize++] = far;
          else
            overflowed = true;
        }
        node = near;
        continue;
      }
    }
    if (stackSize == 0) break;
    node = stack[--stackSize];
  }
  return hit.triangle != 0xffffffffu;
}

#endif
