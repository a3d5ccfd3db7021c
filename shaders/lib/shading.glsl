// The one shading function of hdof: the raster G-buffer and every ray-traced path call it, so a
// surface point gets the same colour whichever way it was found. Needs lib/scene.glsl and
// lib/frame.glsl. No shadows (the raster path has none either): punctual lights with a GGX
// specular lobe, a hemisphere ambient term and emission.
#ifndef HDOF_LIB_SHADING_GLSL
#define HDOF_LIB_SHADING_GLSL


struct SurfacePoint {
  vec3 position;
  vec3 normal;  // interpolated vertex normal, not necessarily facing the viewer
  vec2 uv;
  float uvPerMeter;
  uint material;
};

// The surface point at barycentrics (weights of vertices 1 and 2) of an index-buffer triangle.
SurfacePoint surfaceOfTriangle(uint triangle, vec2 barycentrics) {
  uvec4 corners = sceneTriangle(triangle);
  Vertex a = sceneVertex(corners.x);
  Vertex b = sceneVertex(corners.y);
  Vertex c = sceneVertex(corners.z);
  vec3 w = vec3(1.0 - barycentrics.x - barycentrics.y, barycentrics);
  SurfacePoint s;
  s.position = a.position * w.x + b.position * w.y + c.position * w.z;
  s.normal = a.normal * w.x + b.normal * w.y + c.normal * w.z;
  s.uv = a.uv * w.x + b.uv * w.y + c.uv * w.z;
  s.uvPerMeter = a.uvPerMeter * w.x + b.uvPerMeter * w.y + c.uvPerMeter * w.z;
  s.material = corners.w;
  return s;
}

// Mip level from the pixel's world-space footprint at the point: the same formula in both
// paths, so that raster and ray-traced pixels sample the same texels.
float textureLodAt(SurfacePoint s, float footprint, float cosView) {
  vec2 size = vec2(textureSize(textures, 0).xy);
  float texels = s.uvPerMeter * footprint * max(size.x, size.y) / max(cosView, 0.25);
  return log2(max(texels, 1e-6));
}

float ggxDistribution(float nDotH, float alpha) {
  float a2 = alpha * alpha;
  float d = nDotH * nDotH * (a2 - 1.0) + 1.0;
  return a2 / (kPi * d * d);
}

float smithVisibility(float nDotV, float nDotL, float alpha) {
  float k = alpha * 0.5;
  return 0.25 / ((nDotV * (1.0 - k) + k) * (nDotL * (1.0 - k) + k));
}

// toViewer: unit vector from the point towards the viewer. footprint: world-space size of one
// pixel at the point (distance from the camera times pixelAngle()). Returns the radiance towards
// the viewer; `specular` receives its specular part (for bokeh decisions in the composite).
vec3 shadeSurface(SurfacePoint s, vec3 toViewer, float footprint, out vec3 specular) {
  Material m = sceneMaterial(s.material);
  vec3 n = normalize(s.normal);
  float nDotV = dot(n, toViewer);
  if (nDotV < 0.0) {  // all surfaces are double-sided
    n = -n;
    nDotV = -nDotV;
  }
  nDotV = max(nDotV, 1e-4);
  vec3 baseColor = m.baseColor.rgb;
  if (m.baseColorTexture != kNoTexture) {
    float lod = textureLodAt(s, footprint, nDotV);
    baseColor *= textureLod(textures, vec3(s.uv, float(m.baseColorTexture)), lod).rgb;
  }
  float roughness = clamp(m.roughness, 0.03, 1.0);
  float alpha = roughness * roughness;
  vec3 diffuseColor = baseColor * (1.0 - m.metallic);
  vec3 f0 = mix(vec3(0.04), baseColor, m.metallic);

  vec3 ambient = mix(frame.groundColor, frame.skyColor, n.y * 0.5 + 0.5);
  vec3 diffuse = ambient * diffuseColor;
  specular = ambient * f0 * (1.0 - 0.5 * roughness);

  for (uint i = 0; i < frame.lightCount; ++i) {
    Light light = sceneLight(i);
    vec3 toLight;
    vec3 irradiance = light.color;
    if (light.type == kLightDirectional) {
      toLight = -light.direction;
    } else {
      vec3 d = light.position - s.position;
      float distance2 = max(dot(d, d), 1e-8);
      toLight = d * inversesqrt(distance2);
      irradiance /= distance2;
      if (light.range > 0.0) {
        float ratio = distance2 / (light.range * light.range);
        irradiance *= clamp(1.0 - ratio * ratio, 0.0, 1.0);
      }
      if (light.type == kLightSpot) {
        float cosAngle = dot(-toLight, light.direction);
        irradiance *= smoothstep(light.spotCosOuter, light.spotCosInner, cosAngle);
      }
    }
    float nDotL = dot(n, toLight);
    if (nDotL <= 0.0) continue;
    vec3 h = normalize(toLight + toViewer);
    // Clamped to 1 as well: with the light straight behind the viewer, rounding can put the dot
    // product of unit vectors just above it (with pow(), the negative 1 - vDotH gave NaN: a black
    // pixel that the blurs spread into a black square).
    float nDotH = clamp(dot(n, h), 0.0, 1.0);
    float vDotH = clamp(dot(toViewer, h), 0.0, 1.0);
    // Schlick's (1 - vDotH)^5 as products: pow() is a logarithm and an exponential, slower on a
    // CPU device (the G-buffer's shading step 5% faster on lavapipe).
    float grazing = 1.0 - vDotH;
    float grazing2 = grazing * grazing;
    vec3 fresnel = f0 + (1.0 - f0) * (grazing2 * grazing2 * grazing);
    vec3 lightIn = irradiance * nDotL;
    diffuse += lightIn * diffuseColor * (1.0 / kPi);
    specular +=
        lightIn * fresnel * ggxDistribution(nDotH, alpha) * smithVisibility(nDotV, nDotL, alpha);
  }
  return m.emissive + diffuse + specular;
}

#endif
