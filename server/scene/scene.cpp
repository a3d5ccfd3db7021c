#include "scene/scene.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>

namespace hdof {

const SceneCamera* Scene::findCamera(const std::string& cameraName) const {
  for (const SceneCamera& camera : cameras) {
    if (camera.name == cameraName) return &camera;
  }
  return nullptr;
}

namespace {

std::string lowercaseExtension(const std::string& path) {
  size_t slash = path.find_last_of("/\\");
  size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string extension = path.substr(dot);
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

std::string joinedBuiltinNames() {
  std::string joined;
  for (const std::string& name : builtinSceneNames()) {
    if (!joined.empty()) joined += ", ";
    joined += "builtin:" + name;
  }
  return joined;
}

}  // namespace

Scene loadScene(const std::string& spec) {
  const std::string builtinPrefix = "builtin:";
  if (spec.starts_with(builtinPrefix)) return makeBuiltinScene(spec.substr(builtinPrefix.size()));
  std::string extension = lowercaseExtension(spec);
  if (extension == ".gltf" || extension == ".glb") return loadGltfScene(spec);
  throw SceneError("unknown scene '" + spec + "': give a .gltf or .glb file or one of " +
                   joinedBuiltinNames());
}

namespace {

void validateTopology(const Scene& scene) {
  if (scene.indices.size() % 3 != 0) {
    throw SceneError("index count " + std::to_string(scene.indices.size()) +
                     " is not a multiple of 3");
  }
  if (scene.indices.empty()) throw SceneError("the scene has no triangles");
  // The raster's visibility images hold a triangle's number as a float, exact below 2^24.
  constexpr size_t kMaxTriangles = (size_t(1) << 24) - 1;
  if (scene.triangleCount() > kMaxTriangles)
    throw SceneError("the scene has " + std::to_string(scene.triangleCount()) +
                     " triangles; at most " + std::to_string(kMaxTriangles) + " are supported");
  for (uint32_t index : scene.indices) {
    if (index >= scene.vertices.size()) {
      throw SceneError("vertex index " + std::to_string(index) + " out of range (" +
                       std::to_string(scene.vertices.size()) + " vertices)");
    }
  }
  for (const gpu::Vertex& vertex : scene.vertices) {
    if (vertex.material >= scene.materials.size()) {
      throw SceneError("material " + std::to_string(vertex.material) + " out of range (" +
                       std::to_string(scene.materials.size()) + " materials)");
    }
  }
  for (const gpu::Material& material : scene.materials) {
    if (material.baseColorTexture != gpu::kNoTexture &&
        material.baseColorTexture >= scene.textures.size()) {
      throw SceneError("texture " + std::to_string(material.baseColorTexture) + " out of range");
    }
  }
}

bool isZero(const glm::vec3& v) { return v.x == 0.0f && v.y == 0.0f && v.z == 0.0f; }

// Vertices that came without a normal get the area-weighted average of the faces around them
// (the cross product's length is twice the area); every normal ends up unit length.
void generateMissingNormals(Scene& scene) {
  std::vector<uint8_t> missing(scene.vertices.size());
  bool anyMissing = false;
  for (size_t i = 0; i < scene.vertices.size(); ++i) {
    missing[i] = isZero(scene.vertices[i].normal);
    anyMissing = anyMissing || missing[i];
  }
  if (anyMissing) {
    for (size_t t = 0; t < scene.indices.size(); t += 3) {
      const uint32_t* corner = &scene.indices[t];
      if (!missing[corner[0]] && !missing[corner[1]] && !missing[corner[2]]) continue;
      glm::vec3 p0 = scene.vertices[corner[0]].position;
      glm::vec3 faceNormal = glm::cross(scene.vertices[corner[1]].position - p0,
                                        scene.vertices[corner[2]].position - p0);
      for (int k = 0; k < 3; ++k) {
        if (missing[corner[k]]) scene.vertices[corner[k]].normal += faceNormal;
      }
    }
  }
  for (gpu::Vertex& vertex : scene.vertices) {
    float length = glm::length(vertex.normal);
    // Unreferenced or fully degenerate vertices still need a valid normal for the shaders.
    vertex.normal = (length > 0.0f && std::isfinite(length)) ? vertex.normal / length
                                                             : glm::vec3(0.0f, 1.0f, 0.0f);
  }
}

// Texture-space length per world-space length, for mip selection: per triangle the square root of
// the area ratio, averaged over the triangles around each vertex (zero-area ones carry no scale).
void computeUvPerMeter(Scene& scene) {
  std::vector<float> sum(scene.vertices.size(), 0.0f);
  std::vector<uint32_t> count(scene.vertices.size(), 0);
  for (size_t t = 0; t < scene.indices.size(); t += 3) {
    const uint32_t* corner = &scene.indices[t];
    const gpu::Vertex& a = scene.vertices[corner[0]];
    const gpu::Vertex& b = scene.vertices[corner[1]];
    const gpu::Vertex& c = scene.vertices[corner[2]];
    float worldArea = glm::length(glm::cross(b.position - a.position, c.position - a.position));
    if (!(worldArea > 0.0f) || !std::isfinite(worldArea)) continue;
    glm::vec2 du = b.uv - a.uv, dv = c.uv - a.uv;
    float uvArea = std::abs(du.x * dv.y - du.y * dv.x);
    float ratio = std::sqrt(uvArea / worldArea);
    for (int k = 0; k < 3; ++k) {
      sum[corner[k]] += ratio;
      ++count[corner[k]];
    }
  }
  for (size_t i = 0; i < scene.vertices.size(); ++i) {
    scene.vertices[i].uvPerMeter = count[i] > 0 ? sum[i] / static_cast<float>(count[i]) : 0.0f;
  }
}

// A view from the front and a little above that fits the bounding sphere.
SceneCamera cameraFramingBounds(const Aabb& bounds) {
  SceneCamera camera;
  camera.name = "default";
  camera.yfov = glm::radians(40.0f);
  float radius = std::max(0.5f * glm::length(bounds.extent()), 1e-3f);
  float distance = radius / std::sin(0.5f * camera.yfov);
  glm::vec3 towardsCamera = glm::normalize(glm::vec3(0.0f, 0.35f, 1.0f));
  camera.position = bounds.center() + towardsCamera * distance;
  camera.forward = -towardsCamera;
  camera.up = glm::normalize(
      glm::cross(glm::cross(camera.forward, glm::vec3(0.0f, 1.0f, 0.0f)), camera.forward));
  camera.znear = std::max(1e-3f * distance, 0.01f * radius);
  camera.zfar = distance + 2.0f * radius;
  camera.focusDistance = distance;
  return camera;
}

}  // namespace

void finalizeScene(Scene& scene) {
  validateTopology(scene);
  generateMissingNormals(scene);
  computeUvPerMeter(scene);
  scene.bounds = Aabb{};
  for (const gpu::Vertex& vertex : scene.vertices) scene.bounds.grow(vertex.position);
  if (scene.cameras.empty()) scene.cameras.push_back(cameraFramingBounds(scene.bounds));
}

namespace {

float srgbToLinearExact(float encoded) {
  return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

struct SrgbTables {
  static constexpr int kCoarseSteps = 4096;
  std::array<float, 256> toLinear;
  // roundingThreshold[i]: the linear value whose sRGB encoding is i + 0.5 (in 8-bit steps): a
  // value at or above it rounds to code i + 1 or higher. The coarse table gives the code at the
  // start of each of kCoarseSteps linear intervals, so encoding needs at most a few steps up.
  std::array<float, 256> roundingThreshold;
  std::array<uint8_t, kCoarseSteps + 1> coarseCode;
  SrgbTables() {
    for (int i = 0; i < 256; ++i) {
      toLinear[i] = srgbToLinearExact(static_cast<float>(i) / 255.0f);
      roundingThreshold[i] = i < 255 ? srgbToLinearExact((static_cast<float>(i) + 0.5f) / 255.0f)
                                     : std::numeric_limits<float>::infinity();
    }
    for (int step = 0; step <= kCoarseSteps; ++step) {
      float linear = static_cast<float>(step) / kCoarseSteps;
      auto it = std::upper_bound(roundingThreshold.begin(), roundingThreshold.end(), linear);
      coarseCode[step] = static_cast<uint8_t>(it - roundingThreshold.begin());
    }
  }
  uint8_t encode(float linear) const {
    linear = std::clamp(linear, 0.0f, 1.0f);
    int code = coarseCode[static_cast<int>(linear * kCoarseSteps)];
    while (linear >= roundingThreshold[code]) ++code;
    return static_cast<uint8_t>(code);
  }
};

const SrgbTables& srgbTables() {
  static const SrgbTables tables;
  return tables;
}

// Each destination texel averages the 2x2 source texels under it; on an odd-sized axis the last
// texel also takes in the leftover source row/column, so no source texel is dropped.
Texture::Level downsample(const Texture::Level& source) {
  const SrgbTables& srgb = srgbTables();
  Texture::Level level;
  level.width = std::max(source.width / 2, 1u);
  level.height = std::max(source.height / 2, 1u);
  level.rgba.resize(size_t{level.width} * level.height * 4);
  auto sourceSpan = [](uint32_t destination, uint32_t destinationSize, uint32_t sourceSize) {
    uint32_t first = std::min(2 * destination, sourceSize - 1);
    uint32_t last =
        destination + 1 == destinationSize ? sourceSize - 1 : std::min(first + 1, sourceSize - 1);
    return std::pair{first, last};
  };
  for (uint32_t y = 0; y < level.height; ++y) {
    auto [y0, y1] = sourceSpan(y, level.height, source.height);
    for (uint32_t x = 0; x < level.width; ++x) {
      auto [x0, x1] = sourceSpan(x, level.width, source.width);
      glm::vec4 sum(0.0f);
      for (uint32_t sy = y0; sy <= y1; ++sy) {
        const uint8_t* row = &source.rgba[(size_t{sy} * source.width) * 4];
        for (uint32_t sx = x0; sx <= x1; ++sx) {
          const uint8_t* texel = row + size_t{sx} * 4;
          sum += glm::vec4(srgb.toLinear[texel[0]], srgb.toLinear[texel[1]],
                           srgb.toLinear[texel[2]], static_cast<float>(texel[3]));
        }
      }
      sum /= static_cast<float>((x1 - x0 + 1) * (y1 - y0 + 1));
      uint8_t* out = &level.rgba[(size_t{y} * level.width + x) * 4];
      out[0] = srgb.encode(sum.r);
      out[1] = srgb.encode(sum.g);
      out[2] = srgb.encode(sum.b);
      out[3] = static_cast<uint8_t>(std::lround(sum.a));
    }
  }
  return level;
}

}  // namespace

void buildMipChain(Texture& texture) {
  if (texture.levels.empty()) throw SceneError("texture '" + texture.name + "' has no image");
  const Texture::Level& base = texture.levels.front();
  if (base.width == 0 || base.height == 0 ||
      base.rgba.size() != size_t{base.width} * base.height * 4) {
    throw SceneError("texture '" + texture.name + "' has an invalid size");
  }
  texture.levels.resize(1);
  while (texture.levels.back().width > 1 || texture.levels.back().height > 1) {
    texture.levels.push_back(downsample(texture.levels.back()));
  }
}

}  // namespace hdof
