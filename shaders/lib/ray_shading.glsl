// Shading a ray's closest hit with the shared shading function. Needs scene, frame, shading,
// bvh_traverse.
#ifndef HDOF_LIB_RAY_SHADING_GLSL
#define HDOF_LIB_RAY_SHADING_GLSL

struct RaySample {
  vec3 radiance;
  vec3 specular;
  float distance;  // along the ray; a huge value for a miss
  vec3 position;  // world position of the hit
};

// The radiance a camera ray (from a point of the lens) brings back: its closest hit beyond the
// near clipping plane, shaded, or the sky. The plane is the raster's, so that a camera inside or
// against a wall sees through it in every mode alike.
RaySample traceCameraRay(vec3 origin, vec3 direction) {
  RaySample result;
  RayHit hit;
  bool overflowed;
  float tNear = frame.znear / max(dot(direction, frame.forward), 1e-6);
  if (!traceClosest(origin, direction, tNear, 1e30, hit, overflowed)) {
    result.radiance = frame.skyColor;
    result.specular = vec3(0.0);
    result.distance = 1e30;
    result.position = origin + direction * 1e5;
    return result;
  }
  SurfacePoint s = surfaceOfTriangle(hit.triangle, hit.barycentrics);
  float footprint = length(s.position - frame.eye) * pixelAngle();
  result.radiance = shadeSurface(s, -direction, footprint, result.specular);
  result.distance = hit.t;
  result.position = s.position;
  return result;
}

#endif
