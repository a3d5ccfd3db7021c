// Scene data as the GPU sees it: one world-space vertex/index soup, the same triangles in BVH
// leaf order for traversal, materials, punctual lights. What shaders read per pixel or per ray
// (vertices, triangles, materials, lights, the BVH) lives in RGBA32UI uniform texel buffers as
// rows of 16 bytes: one typed load per row, through the texture cache on GPUs, and a vector gather
// on lavapipe (which loops over the lanes for storage-buffer loads). The C++ side asserts layouts.
#ifndef HDOF_SHARED_SCENE_DATA_H
#define HDOF_SHARED_SCENE_DATA_H
#include "types.h"

HDOF_NAMESPACE_BEGIN

// Descriptor set 0: the scene, shared by every pass and session.
HDOF_CONST uint kSceneSet = 0;
HDOF_CONST uint kBindingVertices = 0;      // PackedVertex rows
HDOF_CONST uint kBindingTriangles = 1;     // uvec4 per triangle: its three vertices and material
HDOF_CONST uint kBindingMaterials = 2;     // PackedMaterial rows
HDOF_CONST uint kBindingLights = 3;        // Light rows
HDOF_CONST uint kBindingBvhNodes = 4;      // BvhWideNode, as an RGBA32UI uniform texel buffer
HDOF_CONST uint kBindingBvhTriangles = 5;  // BvhTriangle, as an RGBA32UI uniform texel buffer
HDOF_CONST uint kBindingTextures = 6;      // one 2D array texture, a layer per scene texture

// Scene textures are resampled to square layers of one array texture, so that any shader can
// pick a texture per pixel without non-uniform descriptor indexing. The layer side is the
// next power of two of the largest texture, at most this.
HDOF_CONST uint kMaxTextureLayerSize = 1024;
HDOF_CONST uint kMaxTextureLayers = 256;

HDOF_CONST uint kNoTexture = 0xffffffffu;

struct Vertex {
  vec3 position;     // world space
  float uvPerMeter;  // texture-space length per world-space length here: picks the mip level
  vec3 normal;       // world space, unit length
  uint material;
  vec2 uv;
};

// A vertex as the shaders read it: two rows, the normal in octahedral form (2 x snorm16).
struct PackedVertex {
  vec3 position;
  float uvPerMeter;
  vec2 uv;
  uint normal;  // packNormal()
  uint material;
};

struct Material {
  vec4 baseColor;  // linear RGB, alpha unused (all opaque)
  vec3 emissive;   // linear RGB radiance
  float metallic;
  float roughness;
  uint baseColorTexture;  // layer of the texture array or kNoTexture
};

HDOF_CONST uint kLightDirectional = 0;
HDOF_CONST uint kLightPoint = 1;
HDOF_CONST uint kLightSpot = 2;

// A material as the shaders read it: three rows.
struct PackedMaterial {
  vec4 baseColor;
  vec3 emissive;
  float metallic;
  float roughness;
  uint baseColorTexture;
  uint unused[2];  // rows are 16 bytes
};

// Octahedral unit-vector encoding (Cigolle et al. 2014), as two snorm16 in one uint.
HDOF_FN vec2 octahedralSign(vec2 v) {
  return vec2(v.x >= 0.0f ? 1.0f : -1.0f, v.y >= 0.0f ? 1.0f : -1.0f);
}
#ifdef __cplusplus
inline uint packNormal(vec3 n) {
  vec2 p = vec2(n.x, n.y) / (abs(n.x) + abs(n.y) + abs(n.z));
  if (n.z < 0.0f) p = (vec2(1.0f) - abs(vec2(p.y, p.x))) * octahedralSign(p);
  return glm::packSnorm2x16(p);
}
#else
vec3 unpackNormal(uint bits) {
  vec2 p = unpackSnorm2x16(bits);
  vec3 n = vec3(p, 1.0 - abs(p.x) - abs(p.y));
  if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * octahedralSign(n.xy);
  return normalize(n);
}
#endif

struct Light {
  vec3 position;  // point, spot
  uint type;
  vec3 direction;  // unit vector the light travels along (directional, spot)
  float range;     // 0: unlimited
  vec3 color;      // colour times intensity (lux for directional, candela otherwise)
  float spotCosInner;
  float spotCosOuter;
  uint unused[3];  // rows are 16 bytes
};

// BVH node as built on the CPU: an interior node's children are nodes leftOrFirst and
// leftOrFirst + 1; a leaf holds triangleCount > 0 triangles starting at leftOrFirst in the
// leaf-ordered triangle array.
struct BvhNode {
  vec3 boundsMin;
  uint leftOrFirst;
  vec3 boundsMax;
  uint triangleCount;
};

// A triangle in leaf order, stored for intersection (vertex and two edges); `index` is the
// triangle's number in the index buffer, for shading. Padded to 48 bytes so that each row is one
// aligned 16-byte load on GPUs.
struct BvhTriangle {
  vec3 v0;
  uint index;
  vec3 edge1;
  float pad0_;
  vec3 edge2;
  float pad1_;
};

// BVH node as the compute shaders traverse it: up to four nodes of the built tree (an interior
// node's children, the widest interior ones replaced by their own children), their boxes
// quantised to 8 bits per plane on a grid that starts at an origin and steps by a power of two per
// axis (the compressed wide BVH of Ylitie et al. 2017). Three 16-byte rows test four boxes; the
// grid rounds every box outwards, never inwards. Child k is byte k of each quantised plane and of
// childInfo: kBvhInteriorChild for a node, kBvhEmptyChild for no child, otherwise a leaf of that
// many triangles. A node's interior children are the nodes from firstNode on, one after the other
// in child order, and its leaves' triangles follow one another from firstTriangle in the packed
// triangle array, in child order (so a child's link is a count of the children before it). Node 0
// holds the root's children. Rows: origin[3], firstNode; lowX, lowY, lowZ, highX; highY, highZ,
// childInfo, firstTriangle.
HDOF_CONST uint kBvhWidth = 4;
HDOF_CONST uint kBvhInteriorChild = 0u;
HDOF_CONST uint kBvhEmptyChild = 0xffu;
HDOF_CONST uint kBvhMaxLeafTriangles = 0xfeu;

struct BvhWideNode {
  // The grid's origin along each axis as float bits whose low byte is the grid's step along that
  // axis (a power of two, as the biased exponent of a float): the origin is rounded down to the
  // 16 bits of mantissa left.
  uint origin[3];
  uint firstNode;
  uint lowX, lowY, lowZ;
  uint highX, highY, highZ;
  uint childInfo;
  uint firstTriangle;
};

HDOF_CONST uint kBvhStackSize = 64;
// The traversal stores a node's first interior child in 24 bits (lib/bvh_traverse.glsl).
HDOF_CONST uint kBvhMaxNodes = 1u << 24u;

HDOF_NAMESPACE_END

#ifdef __cplusplus
#include <cstddef>
static_assert(sizeof(hdof::gpu::Vertex) == 40);
static_assert(offsetof(hdof::gpu::Vertex, normal) == 16);
static_assert(offsetof(hdof::gpu::Vertex, uv) == 32);
static_assert(sizeof(hdof::gpu::Material) == 40);
static_assert(sizeof(hdof::gpu::PackedVertex) == 32);
static_assert(offsetof(hdof::gpu::PackedVertex, uv) == 16);
static_assert(sizeof(hdof::gpu::PackedMaterial) == 48);
static_assert(offsetof(hdof::gpu::PackedMaterial, emissive) == 16);
static_assert(offsetof(hdof::gpu::PackedMaterial, roughness) == 32);
static_assert(sizeof(hdof::gpu::Light) == 64);
static_assert(offsetof(hdof::gpu::Light, color) == 32);
static_assert(sizeof(hdof::gpu::BvhNode) == 32);
static_assert(offsetof(hdof::gpu::BvhNode, boundsMax) == 16);
static_assert(sizeof(hdof::gpu::BvhTriangle) == 48);
static_assert(sizeof(hdof::gpu::BvhWideNode) == 48);
static_assert(offsetof(hdof::gpu::BvhWideNode, lowX) == 16);
static_assert(offsetof(hdof::gpu::BvhWideNode, highY) == 32);
static_assert(offsetof(hdof::gpu::BvhWideNode, firstTriangle) == 44);
#endif

#endif
