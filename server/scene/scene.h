// The CPU-side scene: a world-space triangle soup with materials, textures, lights and cameras,
// loaded from glTF or built procedurally. Immutable once loaded; shared by all sessions.
#pragma once

#include <shared/scene_data.h>

#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace hdof {

// Bad scene input (missing file, corrupt glTF, unknown built-in): a message for the user.
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Aabb {
  glm::vec3 min{std::numeric_limits<float>::max()};
  glm::vec3 max{-std::numeric_limits<float>::max()};
  void grow(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void grow(const Aabb& b) {
    min = glm::min(min, b.min);
    max = glm::max(max, b.max);
  }
  bool empty() const { return min.x > max.x; }
  glm::vec3 center() const { return (min + max) * 0.5f; }
  glm::vec3 extent() const { return max - min; }
  float surfaceArea() const {
    glm::vec3 e = glm::max(extent(), glm::vec3(0.0f));
    return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
};

// An 8-bit RGBA texture in sRGB encoding with its full mip chain (level 0 first, each level half
// the size of the one before, rounded down, at least 1).
struct Texture {
  std::string name;
  struct Level {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgba;
  };
  std::vector<Level> levels;
};

struct SceneCamera {
  std::string name;
  glm::vec3 position{0.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};  // unit
  glm::vec3 up{0.0f, 1.0f, 0.0f};        // unit, orthogonal to forward
  float yfov = 0.7f;                     // radians
  float znear = 0.05f;
  float zfar = 1000.0f;
  std::optional<float> focusDistance;  // a suggested focus distance (m), where the scene knows one
};

struct Scene {
  std::string name;
  std::vector<gpu::Vertex> vertices;     // world space; vertices are not shared across materials
  std::vector<uint32_t> indices;         // three per triangle
  std::vector<gpu::Material> materials;  // at least one
  std::vector<Texture> textures;         // referenced by Material::baseColorTexture
  std::vector<gpu::Light> lights;
  std::vector<SceneCamera> cameras;  // at least one: loaders add a default view of the bounds
  glm::vec3 skyColor{0.25f, 0.28f, 0.33f};     // ambient radiance from above, linear
  glm::vec3 groundColor{0.08f, 0.07f, 0.06f};  // ambient radiance from below, linear
  Aabb bounds;

  size_t triangleCount() const { return indices.size() / 3; }
  // The camera with this name, or nullptr.
  const SceneCamera* findCamera(const std::string& cameraName) const;
};

// Loads "builtin:NAME" or a .gltf/.glb path. Throws SceneError with a one-line message.
Scene loadScene(const std::string& spec);

// Names of the built-in scenes, the default one first.
std::vector<std::string> builtinSceneNames();
Scene makeBuiltinScene(const std::string& name);  // throws SceneError for an unknown name
Scene loadGltfScene(const std::string& path);     // throws SceneError

// Shared finishing steps for loaders: generates missing normals, computes per-vertex
// uvPerMeter, the bounds, and a default camera when the scene has none.
void finalizeScene(Scene& scene);

// Builds the mip chain of an sRGB RGBA8 texture from its level 0 (filters in linear space).
void buildMipChain(Texture& texture);

}  // namespace hdof
