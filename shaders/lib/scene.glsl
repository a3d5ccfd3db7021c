// Set 0: the scene, as every pass that reads it declares it.
#ifndef HDOF_LIB_SCENE_GLSL
#define HDOF_LIB_SCENE_GLSL
#extension GL_EXT_scalar_block_layout : require
#include "shared/scene_data.h"

layout(set = 0, binding = kBindingVertices, scalar) readonly buffer Vertices { Vertex vertices[]; };
layout(set = 0, binding = kBindingIndices, scalar) readonly buffer Indices { uint indices[]; };
layout(set = 0, binding = kBindingMaterials, scalar) readonly buffer Materials { Material materials[]; };
layout(set = 0, binding = kBindingLights, scalar) readonly buffer Lights { Light lights[]; };
// The BVH bindings are declared by lib/bvh_traverse.glsl, which reads them as aligned rows.
layout(set = 0, binding = kBindingTextures) uniform sampler2DArray textures;

#endif
