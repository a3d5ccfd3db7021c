// Procedural content for the built-in scenes: shapes appended to a Scene in world space, with
// texture coordinates proportional to world lengths, and tileable sRGB textures with mip chains.
#pragma once

#include "scene/scene.h"

namespace hdof::procedural {

struct Surface {
  uint32_t material = 0;
  float texelRepeatsPerMeter = 1.0f;  // how many times the texture repeats per metre of surface
};

gpu::Material makeMaterial(const glm::vec3& baseColor, float roughness, float metallic = 0.0f,
                           uint32_t texture = gpu::kNoTexture,
                           const glm::vec3& emissive = glm::vec3(0.0f));
uint32_t addMaterial(Scene& scene, const gpu::Material& material);
uint32_t addTexture(Scene& scene, Texture texture);

// A parallelogram from `corner` spanned by two edges, split into subdivisions^2 cells; it faces
// along cross(edgeU, edgeV).
void addQuad(Scene& scene, const glm::vec3& corner, const glm::vec3& edgeU, const glm::vec3& edgeV,
             const Surface& surface, uint32_t subdivisions = 1);
// A box around `center`, turned by `yaw` radians about the vertical axis.
void addBox(Scene& scene, const glm::vec3& center, const glm::vec3& halfExtent, float yaw,
            const Surface& surface);
void addSphere(Scene& scene, const glm::vec3& center, float radius, const Surface& surface,
               uint32_t rings = 16);
// An upright capped cylinder standing on `baseCenter`.
void addCylinder(Scene& scene, const glm::vec3& baseCenter, float radius, float height,
                 const Surface& surface, uint32_t segments = 16);

// Tileable textures of size x size texels (size a power of two).
Texture bricksTexture(uint32_t size);
Texture tilesTexture(uint32_t size);
Texture planksTexture(uint32_t size);
Texture stoneTexture(uint32_t size);
Texture checkerTexture(uint32_t size);

}  // namespace hdof::procedural
