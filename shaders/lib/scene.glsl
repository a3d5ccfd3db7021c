// Set 0: the scene, as every step that reads it declares it.
#ifndef HDOF_LIB_SCENE_GLSL
#define HDOF_LIB_SCENE_GLSL
#include "shared/scene_data.h"

layout(set = 0, binding = kBindingVertices) uniform usamplerBuffer vertexTexels;
layout(set = 0, binding = kBindingTriangles) uniform usamplerBuffer triangleTexels;
layout(set = 0, binding = kBindingMaterials) uniform usamplerBuffer materialTexels;
layout(set = 0, binding = kBindingLights) uniform usamplerBuffer lightTexels;
// The BVH bindings are declared by lib/bvh_traverse.glsl, which alone reads them.

// The three vertices (xyz) and the material (w) of an index-buffer triangle.
uvec4 sceneTriangle(uint triangle) { return texelFetch(triangleTexels, int(triangle)); }

vec3 vertexPosition(uint vertex) {
  return uintBitsToFloat(texelFetch(vertexTexels, int(vertex * 2u)).xyz);
}

Vertex sceneVertex(uint vertex) {
  uvec4 row0 = texelFetch(vertexTexels, int(vertex * 2u));
  uvec4 row1 = texelFetch(vertexTexels, int(vertex * 2u + 1u));
  Vertex v;
  v.position = uintBitsToFloat(row0.xyz);
  v.uvPerMeter = uintBitsToFloat(row0.w);
  v.uv = uintBitsToFloat(row1.xy);
  v.normal = unpackNormal(row1.z);
  v.material = row1.w;
  return v;
}

Material sceneMaterial(uint material) {
  uvec4 row0 = texelFetch(materialTexels, int(material * 3u));
  uvec4 row1 = texelFetch(materialTexels, int(material * 3u + 1u));
  uvec4 row2 = texelFetch(materialTexels, int(material * 3u + 2u));
  Material m;
  m.baseColor = uintBitsToFloat(row0);
  m.emissive = uintBitsToFloat(row1.xyz);
  m.metallic = uintBitsToFloat(row1.w);
  m.roughness = uintBitsToFloat(row2.x);
  m.baseColorTexture = row2.y;
  return m;
}

Light sceneLight(uint light) {
  vec4 row0 = uintBitsToFloat(texelFetch(lightTexels, int(light * 4u)));
  vec4 row1 = uintBitsToFloat(texelFetch(lightTexels, int(light * 4u + 1u)));
  vec4 row2 = uintBitsToFloat(texelFetch(lightTexels, int(light * 4u + 2u)));
  Light l;
  l.position = row0.xyz;
  l.type = floatBitsToUint(row0.w);
  l.direction = row1.xyz;
  l.range = row1.w;
  l.color = row2.xyz;
  l.spotCosInner = row2.w;
  l.spotCosOuter = uintBitsToFloat(texelFetch(lightTexels, int(light * 4u + 3u)).x);
  return l;
}

layout(set = 0, binding = kBindingTextures) uniform sampler2DArray textures;

#endif
