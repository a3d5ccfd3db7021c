#include "scene/procedural.h"

#include <glm/gtc/constants.hpp>

#include <cmath>
#include <functional>

namespace hdof::procedural {

gpu::Material makeMaterial(const glm::vec3& baseColor, float roughness, float metallic,
                           uint32_t texture, const glm::vec3& emissive) {
  return gpu::Material{glm::vec4(baseColor, 1.0f), emissive, metallic, roughness, texture};
}

uint32_t addMaterial(Scene& scene, const gpu::Material& material) {
  scene.materials.push_back(material);
  return static_cast<uint32_t>(scene.materials.size() - 1);
}

uint32_t addTexture(Scene& scene, Texture texture) {
  scene.textures.push_back(std::move(texture));
  return static_cast<uint32_t>(scene.textures.size() - 1);
}

namespace {

uint32_t appendVertex(Scene& scene, const glm::vec3& position, const glm::vec3& normal,
                      const glm::vec2& uv, uint32_t material) {
  scene.vertices.push_back(gpu::Vertex{position, 0.0f, normal, material, uv});
  return static_cast<uint32_t>(scene.vertices.size() - 1);
}

void appendTriangle(Scene& scene, uint32_t a, uint32_t b, uint32_t c) {
  scene.indices.insert(scene.indices.end(), {a, b, c});
}

// Triangles over a (columns + 1) x (rows + 1) vertex grid that starts at `first`, row by row.
void appendGridTriangles(Scene& scene, uint32_t first, uint32_t columns, uint32_t rows) {
  for (uint32_t row = 0; row < rows; ++row) {
    for (uint32_t column = 0; column < columns; ++column) {
      uint32_t a = first + row * (columns + 1) + column;
      uint32_t b = a + 1, c = a + columns + 1, d = c + 1;
      appendTriangle(scene, a, b, d);
      appendTriangle(scene, a, d, c);
    }
  }
}

}  // namespace

void addQuad(Scene& scene, const glm::vec3& corner, const glm::vec3& edgeU, const glm::vec3& edgeV,
             const Surface& surface, uint32_t subdivisions) {
  glm::vec3 normal = glm::normalize(glm::cross(edgeU, edgeV));
  // Texture rows run downwards: v grows against edgeV so images are upright on walls.
  glm::vec2 uvSpan =
      glm::vec2(glm::length(edgeU), -glm::length(edgeV)) * surface.texelRepeatsPerMeter;
  uint32_t first = static_cast<uint32_t>(scene.vertices.size());
  for (uint32_t j = 0; j <= subdivisions; ++j) {
    for (uint32_t i = 0; i <= subdivisions; ++i) {
      glm::vec2 st = glm::vec2(i, j) / static_cast<float>(subdivisions);
      appendVertex(scene, corner + st.x * edgeU + st.y * edgeV, normal, st * uvSpan,
                   surface.material);
    }
  }
  appendGridTriangles(scene, first, subdivisions, subdivisions);
}

void addBox(Scene& scene, const glm::vec3& center, const glm::vec3& halfExtent, float yaw,
            const Surface& surface) {
  glm::mat3 rotation(glm::vec3(std::cos(yaw), 0.0f, -std::sin(yaw)), glm::vec3(0.0f, 1.0f, 0.0f),
                     glm::vec3(std::sin(yaw), 0.0f, std::cos(yaw)));
  // Per face: the outward axis and two in-plane axes with cross(u, v) == outward.
  struct Face {
    glm::vec3 outward, u, v;
  };
  const Face faces[] = {
      {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
      {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
  };
  for (const Face& face : faces) {
    glm::vec3 toFace = rotation * (face.outward * halfExtent);
    glm::vec3 halfU = rotation * (face.u * halfExtent);
    glm::vec3 halfV = rotation * (face.v * halfExtent);
    addQuad(scene, center + toFace - halfU - halfV, 2.0f * halfU, 2.0f * halfV, surface);
  }
}

void addSphere(Scene& scene, const glm::vec3& center, float radius, const Surface& surface,
               uint32_t rings) {
  uint32_t segments = 2 * rings;
  uint32_t first = static_cast<uint32_t>(scene.vertices.size());
  for (uint32_t ring = 0; ring <= rings; ++ring) {
    float theta = glm::pi<float>() * static_cast<float>(ring) / static_cast<float>(rings);
    for (uint32_t segment = 0; segment <= segments; ++segment) {
      float phi = glm::two_pi<float>() * static_cast<float>(segment) / static_cast<float>(segments);
      glm::vec3 normal(std::sin(theta) * std::cos(phi), std::cos(theta),
                       -std::sin(theta) * std::sin(phi));
      glm::vec2 uv = glm::vec2(phi, theta) * radius * surface.texelRepeatsPerMeter;
      appendVertex(scene, center + radius * normal, normal, uv, surface.material);
    }
  }
  // The grid's triangles, less the zero-area ones that touch the poles.
  for (uint32_t ring = 0; ring < rings; ++ring) {
    for (uint32_t segment = 0; segment < segments; ++segment) {
      uint32_t a = first + ring * (segments + 1) + segment;
      uint32_t b = a + 1, c = a + segments + 1, d = c + 1;
      if (ring > 0) appendTriangle(scene, a, c, b);
      if (ring + 1 < rings) appendTriangle(scene, b, c, d);
    }
  }
}

void addCylinder(Scene& scene, const glm::vec3& baseCenter, float radius, float height,
                 const Surface& surface, uint32_t segments) {
  float repeats = surface.texelRepeatsPerMeter;
  auto radial = [&](uint32_t segment) {
    float phi = glm::two_pi<float>() * static_cast<float>(segment) / static_cast<float>(segments);
    return glm::vec3(std::cos(phi), 0.0f, -std::sin(phi));
  };
  uint32_t side = static_cast<uint32_t>(scene.vertices.size());
  for (uint32_t row = 0; row <= 1; ++row) {
    for (uint32_t segment = 0; segment <= segments; ++segment) {
      glm::vec3 normal = radial(segment);
      float arc = glm::two_pi<float>() * radius * static_cast<float>(segment) /
                  static_cast<float>(segments);
      glm::vec2 uv = glm::vec2(arc, -height * static_cast<float>(row)) * repeats;
      appendVertex(scene, baseCenter + radius * normal + glm::vec3(0.0f, height * row, 0.0f),
                   normal, uv, surface.material);
    }
  }
  appendGridTriangles(scene, side, segments, 1);
  for (float capHeight : {0.0f, height}) {
    glm::vec3 normal(0.0f, capHeight > 0.0f ? 1.0f : -1.0f, 0.0f);
    glm::vec3 capCenter = baseCenter + glm::vec3(0.0f, capHeight, 0.0f);
    uint32_t middle = appendVertex(scene, capCenter, normal, glm::vec2(0.0f), surface.material);
    for (uint32_t segment = 0; segment <= segments; ++segment) {
      glm::vec3 offset = radius * radial(segment);
      appendVertex(scene, capCenter + offset, normal, glm::vec2(offset.x, offset.z) * repeats,
                   surface.material);
    }
    for (uint32_t segment = 0; segment < segments; ++segment) {
      appendTriangle(scene, middle, middle + 1 + segment, middle + 2 + segment);
    }
  }
}

namespace {

uint32_t hash(uint32_t x, uint32_t y, uint32_t seed) {
  uint32_t h = x * 0x8da6b343u ^ y * 0xd8163841u ^ seed * 0xcb1ab31fu;
  h ^= h >> 15;
  h *= 0x2c1b3c6du;
  h ^= h >> 12;
  h *= 0x297a2d39u;
  h ^= h >> 15;
  return h;
}

float hash01(uint32_t x, uint32_t y, uint32_t seed) {
  return static_cast<float>(hash(x, y, seed) >> 8) * (1.0f / 16777216.0f);
}

// Value noise with `period` lattice cells across the unit square on each axis; the lattice wraps,
// so a texture built from it tiles.
float valueNoise(glm::vec2 uv, glm::uvec2 period, uint32_t seed) {
  glm::vec2 p = uv * glm::vec2(period);
  glm::vec2 cell = glm::floor(p);
  glm::vec2 f = p - cell;
  f = f * f * (3.0f - 2.0f * f);
  auto lattice = [&](int dx, int dy) {
    auto wrap = [](int value, uint32_t size) {
      int m = value % static_cast<int>(size);
      return static_cast<uint32_t>(m < 0 ? m + static_cast<int>(size) : m);
    };
    return hash01(wrap(static_cast<int>(cell.x) + dx, period.x),
                  wrap(static_cast<int>(cell.y) + dy, period.y), seed);
  };
  return glm::mix(glm::mix(lattice(0, 0), lattice(1, 0), f.x),
                  glm::mix(lattice(0, 1), lattice(1, 1), f.x), f.y);
}

// Fractal sum of octaves, each at twice the frequency and half the amplitude; result in [0, 1].
float fbm(glm::vec2 uv, glm::uvec2 period, int octaves, uint32_t seed) {
  float sum = 0.0f, amplitude = 0.5f, total = 0.0f;
  for (int octave = 0; octave < octaves; ++octave) {
    sum += amplitude * valueNoise(uv, period << static_cast<uint32_t>(octave), seed + octave);
    total += amplitude;
    amplitude *= 0.5f;
  }
  return sum / total;
}

float linearToSrgb(float linear) {
  linear = glm::clamp(linear, 0.0f, 1.0f);
  return linear <= 0.0031308f ? linear * 12.92f : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

// Evaluates a linear-colour pattern over [0, 1)^2 at texel centres into an sRGB texture.
Texture renderTexture(const std::string& name, uint32_t size,
                      const std::function<glm::vec3(glm::vec2)>& pattern) {
  Texture texture;
  texture.name = name;
  Texture::Level& level = texture.levels.emplace_back();
  level.width = level.height = size;
  level.rgba.resize(size_t{size} * size * 4);
  for (uint32_t y = 0; y < size; ++y) {
    for (uint32_t x = 0; x < size; ++x) {
      glm::vec3 color = pattern((glm::vec2(x, y) + 0.5f) / static_cast<float>(size));
      uint8_t* out = &level.rgba[(size_t{y} * size + x) * 4];
      for (int c = 0; c < 3; ++c) {
        out[c] = static_cast<uint8_t>(std::lround(linearToSrgb(color[c]) * 255.0f));
      }
      out[3] = 255;
    }
  }
  buildMipChain(texture);
  return texture;
}

// A running bond of `columns` x `rows` blocks per tile (odd rows shifted by half a block when
// `staggered`), with joints `joint` wide in texture units. Returns the block's id or -1 on a joint.
struct BlockCoordinate {
  int id = -1;
  glm::vec2 local{0.0f};  // position inside the block, 0..1
};

BlockCoordinate blockAt(glm::vec2 uv, int columns, int rows, float joint, bool staggered) {
  int row = static_cast<int>(uv.y * static_cast<float>(rows));
  float x = uv.x * static_cast<float>(columns) + (staggered && (row & 1) ? 0.5f : 0.0f);
  int column = static_cast<int>(std::floor(x)) % columns;
  glm::vec2 local(x - std::floor(x), uv.y * static_cast<float>(rows) - static_cast<float>(row));
  bool onJoint =
      local.x < joint * static_cast<float>(columns) || local.y < joint * static_cast<float>(rows);
  return {onJoint ? -1 : row * columns + column, local};
}

}  // namespace

Texture bricksTexture(uint32_t size) {
  return renderTexture("bricks", size, [](glm::vec2 uv) {
    BlockCoordinate brick = blockAt(uv, 4, 8, 0.012f, true);
    float grain = fbm(uv, {16, 16}, 4, 11);
    if (brick.id < 0) return glm::vec3(0.32f, 0.30f, 0.27f) * (0.7f + 0.5f * grain);
    auto id = static_cast<uint32_t>(brick.id);
    glm::vec3 red(0.33f, 0.09f, 0.045f), brown(0.30f, 0.16f, 0.08f);
    glm::vec3 color = glm::mix(red, brown, hash01(id, 1, 5)) * (0.65f + 0.7f * hash01(id, 2, 5));
    float soot = fbm(uv + glm::vec2(0.37f, 0.11f), {64, 64}, 3, 13);
    return color * (0.55f + 0.8f * grain * soot);
  });
}

Texture tilesTexture(uint32_t size) {
  return renderTexture("tiles", size, [](glm::vec2 uv) {
    BlockCoordinate tile = blockAt(uv, 4, 4, 0.008f, false);
    float grain = fbm(uv, {32, 32}, 5, 21);
    if (tile.id < 0) return glm::vec3(0.06f, 0.055f, 0.05f) * (0.6f + 0.8f * grain);
    auto id = static_cast<uint32_t>(tile.id);
    glm::vec3 stone =
        glm::mix(glm::vec3(0.30f, 0.27f, 0.23f), glm::vec3(0.20f, 0.21f, 0.22f), hash01(id, 3, 7));
    float speckle =
        hash01(static_cast<uint32_t>(uv.x * 4096.0f), static_cast<uint32_t>(uv.y * 4096.0f), 9);
    return stone * (0.6f + 0.7f * grain) * (speckle > 0.97f ? 0.5f : 1.0f);
  });
}

Texture planksTexture(uint32_t size) {
  return renderTexture("planks", size, [](glm::vec2 uv) {
    const int planks = 6;
    int plank = static_cast<int>(uv.y * planks);
    float across = uv.y * planks - static_cast<float>(plank);
    auto id = static_cast<uint32_t>(plank);
    float endJoint = hash01(id, 4, 3);
    float along = uv.x - endJoint - std::floor(uv.x - endJoint);
    if (across < 0.04f || along < 0.006f) return glm::vec3(0.03f, 0.02f, 0.012f);
    // Grain: stretched noise along the plank, bent into rings.
    float warp = fbm(uv + glm::vec2(0.0f, 0.13f * static_cast<float>(plank)), {4, 48}, 4, 17);
    float rings = 0.5f + 0.5f * std::sin((across * 3.0f + warp * 10.0f + endJoint * 20.0f) *
                                         glm::pi<float>());
    glm::vec3 light(0.42f, 0.24f, 0.11f), dark(0.20f, 0.10f, 0.04f);
    return glm::mix(dark, light, rings * 0.7f + 0.3f * warp) * (0.8f + 0.4f * hash01(id, 5, 3));
  });
}

Texture stoneTexture(uint32_t size) {
  return renderTexture("stone", size, [](glm::vec2 uv) {
    float cloud = fbm(uv, {4, 4}, 6, 31);
    float vein = std::abs(std::sin((uv.x + uv.y + 2.5f * cloud) * 4.0f * glm::pi<float>()));
    glm::vec3 base =
        glm::mix(glm::vec3(0.62f, 0.60f, 0.56f), glm::vec3(0.36f, 0.35f, 0.34f), cloud);
    return base * (0.55f + 0.45f * glm::smoothstep(0.0f, 0.25f, vein));
  });
}

Texture checkerTexture(uint32_t size) {
  return renderTexture("checker", size, [](glm::vec2 uv) {
    const int cells = 8;
    int cx = static_cast<int>(uv.x * cells), cy = static_cast<int>(uv.y * cells);
    glm::vec2 local = uv * static_cast<float>(cells) - glm::vec2(cx, cy);
    // A thin line in each cell adds detail finer than the cells for judging focus.
    bool line = std::abs(local.x - local.y) < 0.02f;
    bool white = ((cx + cy) & 1) != line;
    glm::vec3 tint = glm::mix(glm::vec3(0.9f, 0.35f, 0.1f), glm::vec3(0.1f, 0.4f, 0.9f),
                              hash01(static_cast<uint32_t>(cx), static_cast<uint32_t>(cy), 41));
    return white ? glm::vec3(0.8f) : 0.08f * tint;
  });
}

}  // namespace hdof::procedural
