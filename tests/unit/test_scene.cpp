// Scene loading (glTF, built-in scenes), the shared finishing steps and texture mip chains.
#include "scene/bvh.h"
#include "scene/scene.h"

#include <gtest/gtest.h>

#include <glm/gtc/constants.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <unistd.h>

namespace hdof {
namespace {

namespace fs = std::filesystem;

const std::string kLivingRoom =
    std::string(HDOF_ASSETS_DIR) + "/scenes/living-room/living-room.gltf";

const Scene& livingRoom() {
  static const Scene scene = loadScene(kLivingRoom);
  return scene;
}

// A directory of its own for each test, removed afterwards (tests may run in parallel).
class TempDir {
 public:
  TempDir() {
    const auto* test = testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("hdof-scene-" + std::string(test->name()) + "-" + std::to_string(getpid()));
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string write(const std::string& name, const std::string& content) const {
    std::string file = (path_ / name).string();
    std::ofstream(file, std::ios::binary) << content;
    return file;
  }

 private:
  fs::path path_;
};

// The message of the SceneError that `load` throws; fails the test when it throws none.
template <typename Load>
std::string sceneErrorOf(Load load) {
  try {
    load();
  } catch (const SceneError& error) {
    std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
    return message;
  }
  ADD_FAILURE() << "no SceneError";
  return {};
}

void expectUnit(const glm::vec3& v, float tolerance = 1e-4f) {
  EXPECT_NEAR(glm::length(v), 1.0f, tolerance) << v.x << " " << v.y << " " << v.z;
}

void expectValidCamera(const SceneCamera& camera) {
  expectUnit(camera.forward);
  expectUnit(camera.up);
  EXPECT_NEAR(glm::dot(camera.forward, camera.up), 0.0f, 1e-4f);
  EXPECT_GT(camera.yfov, 0.1f);
  EXPECT_LT(camera.yfov, 2.0f);
  EXPECT_GT(camera.znear, 0.0f);
  EXPECT_GT(camera.zfar, camera.znear);
}

void expectCompleteMipChain(const Texture& texture) {
  ASSERT_FALSE(texture.levels.empty());
  for (size_t i = 1; i < texture.levels.size(); ++i) {
    const Texture::Level& above = texture.levels[i - 1];
    const Texture::Level& level = texture.levels[i];
    EXPECT_EQ(level.width, std::max(above.width / 2, 1u));
    EXPECT_EQ(level.height, std::max(above.height / 2, 1u));
  }
  for (const Texture::Level& level : texture.levels) {
    EXPECT_EQ(level.rgba.size(), size_t{level.width} * level.height * 4);
  }
  EXPECT_EQ(texture.levels.back().width, 1u);
  EXPECT_EQ(texture.levels.back().height, 1u);
}

void expectConsistent(const Scene& scene) {
  ASSERT_GT(scene.triangleCount(), 0u);
  ASSERT_FALSE(scene.materials.empty());
  for (uint32_t index : scene.indices) ASSERT_LT(index, scene.vertices.size());
  for (const gpu::Vertex& vertex : scene.vertices) {
    expectUnit(vertex.normal);
    ASSERT_LT(vertex.material, scene.materials.size());
    ASSERT_GE(vertex.uvPerMeter, 0.0f);
    ASSERT_TRUE(std::isfinite(vertex.uvPerMeter));
  }
  for (const gpu::Material& material : scene.materials) {
    if (material.baseColorTexture != gpu::kNoTexture) {
      ASSERT_LT(material.baseColorTexture, scene.textures.size());
    }
  }
  for (const Texture& texture : scene.textures) expectCompleteMipChain(texture);
  for (const gpu::Light& light : scene.lights) {
    if (light.type != gpu::kLightPoint) expectUnit(light.direction);
  }
  for (const SceneCamera& camera : scene.cameras) expectValidCamera(camera);
  EXPECT_FALSE(scene.bounds.empty());
}

TEST(LivingRoom, LoadsWithTheExpectedContent) {
  const Scene& scene = livingRoom();
  expectConsistent(scene);
  EXPECT_EQ(scene.triangleCount(), 143163u);
  EXPECT_EQ(scene.materials.size(), 19u);  // all of the file's, none missing
  EXPECT_EQ(scene.textures.size(), 3u);
  for (const Texture& texture : scene.textures) EXPECT_GE(texture.levels.size(), 11u);

  ASSERT_EQ(scene.lights.size(), 2u);
  int directional = 0, point = 0;
  for (const gpu::Light& light : scene.lights) {
    if (light.type == gpu::kLightDirectional) {
      ++directional;
      EXPECT_LT(light.direction.y, -0.5f) << "the sun shines downwards";
      EXPECT_NEAR(light.color.r, 3.0f, 1e-4f);
    } else if (light.type == gpu::kLightPoint) {
      ++point;
      EXPECT_NEAR(glm::distance(light.position, glm::vec3(1.5f, 2.4f, -1.0f)), 0.0f, 1e-5f);
      EXPECT_NEAR(light.color.g, 18.0f, 1e-4f);
    }
  }
  EXPECT_EQ(directional, 1);
  EXPECT_EQ(point, 1);

  EXPECT_EQ(scene.cameras.size(), 2u);
  const SceneCamera* closeup = scene.findCamera("closeup");
  const SceneCamera* overview = scene.findCamera("overview");
  ASSERT_NE(closeup, nullptr);
  ASSERT_NE(overview, nullptr);
  EXPECT_EQ(scene.findCamera("no such camera"), nullptr);
  EXPECT_NEAR(closeup->yfov, glm::radians(40.0f), 1e-4f);
  EXPECT_NEAR(glm::distance(closeup->position, glm::vec3(0.45f, 0.72f, -3.42f)), 0.0f, 1e-5f);
  EXPECT_NEAR(overview->forward.x, -0.961792f, 1e-4f);  // the node matrix's -Z column

  // A room of a few metres, standing on y = 0, with both cameras inside it.
  glm::vec3 extent = scene.bounds.extent();
  EXPECT_GT(glm::min(extent.x, extent.z), 2.0f);
  EXPECT_LT(glm::max(extent.x, glm::max(extent.y, extent.z)), 20.0f);
  EXPECT_NEAR(scene.bounds.min.y, 0.0f, 0.05f);
  for (const SceneCamera* camera : {closeup, overview}) {
    EXPECT_TRUE(glm::all(glm::greaterThan(camera->position, scene.bounds.min)));
    EXPECT_TRUE(glm::all(glm::lessThan(camera->position, scene.bounds.max)));
  }
}

TEST(LivingRoom, CamerasLookIntoTheRoom) {
  const Scene& scene = livingRoom();
  Bvh bvh = buildBvh(scene.vertices, scene.indices);
  float diagonal = glm::length(scene.bounds.extent());
  for (const SceneCamera& camera : scene.cameras) {
    std::optional<RayHit> hit = intersect(bvh, camera.position, camera.forward);
    ASSERT_TRUE(hit.has_value()) << camera.name;
    EXPECT_GT(hit->t, 1.0f) << camera.name << " is not up against something";
    EXPECT_LT(hit->t, diagonal) << camera.name << " looks out of the room";
  }
}

TEST(SceneLoading, BadInputsThrowSceneErrors) {
  TempDir dir;
  std::string missing = dir.write("placeholder", "") + "-missing.gltf";
  EXPECT_NE(sceneErrorOf([&] { loadScene(missing); }).find(missing), std::string::npos);
  std::string garbage = dir.write("garbage.gltf", "{ this is not json ]]");
  EXPECT_NE(sceneErrorOf([&] { loadScene(garbage); }).find("garbage.gltf"), std::string::npos);
  std::string garbageBinary = dir.write("garbage.glb", std::string("glTF\x02\0\0\0junk", 12));
  sceneErrorOf([&] { loadScene(garbageBinary); });
  std::string emptyJson = dir.write("empty.gltf", "{}");
  sceneErrorOf([&] { loadScene(emptyJson); });
  std::string noTriangles = dir.write("nothing.gltf", R"({"asset": {"version": "2.0"}})");
  EXPECT_NE(sceneErrorOf([&] { loadScene(noTriangles); }).find("no triangles"), std::string::npos);
  std::string needsDraco = dir.write("draco.gltf", R"({"asset": {"version": "2.0"},
      "extensionsRequired": ["KHR_draco_mesh_compression"],
      "extensionsUsed": ["KHR_draco_mesh_compression"]})");
  EXPECT_NE(sceneErrorOf([&] { loadScene(needsDraco); }).find("KHR_draco_mesh_compression"),
            std::string::npos);

  EXPECT_NE(sceneErrorOf([] { loadScene("room.obj"); }).find("room.obj"), std::string::npos);
  EXPECT_NE(sceneErrorOf([] { loadScene("no-extension"); }).find("builtin:dof"), std::string::npos);
  EXPECT_NE(sceneErrorOf([] { loadScene("builtin:nope"); }).find("nope"), std::string::npos);
  sceneErrorOf([] { makeBuiltinScene(""); });
}

// Binary data for a small glTF: three positions, then three ubyte indices (padded).
std::string smallGltfBuffer() {
  const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::string data(reinterpret_cast<const char*>(positions), sizeof(positions));
  data += std::string("\x00\x01\x02\x00", 4);
  return data;
}

// A hierarchy (translated parent, rotated and scaled child) holding an indexed primitive without
// normals, a non-indexed primitive without a material and a point primitive; a spot light; a
// camera known only by its node's name; an emissive material with a strength.
const char* kSmallGltf = R"({
  "asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],
  "extensions": {"KHR_lights_punctual": {"lights": [
    {"type": "spot", "color": [1, 0.5, 0.25], "intensity": 10,
     "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}]}},
  "scene": 0,
  "scenes": [{"nodes": [0, 3]}],
  "nodes": [
    {"name": "parent", "translation": [10, 0, 0], "children": [1, 2]},
    {"name": "child", "mesh": 0, "rotation": [0, 0.7071068, 0, 0.7071068], "scale": [2, 2, 2]},
    {"name": "lamp", "translation": [0, 3, 0], "rotation": [-0.7071068, 0, 0, 0.7071068],
     "extensions": {"KHR_lights_punctual": {"light": 0}}},
    {"name": "eye", "camera": 0, "translation": [0, 1, 5]}
  ],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
  "meshes": [{"name": "thing", "primitives": [
    {"attributes": {"POSITION": 0}, "indices": 1, "material": 0},
    {"attributes": {"POSITION": 0}},
    {"attributes": {"POSITION": 0}, "mode": 0}
  ]}],
  "materials": [{"emissiveFactor": [1, 0.5, 0],
                 "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}}],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
     "min": [0, 0, 0], "max": [1, 1, 0]},
    {"bufferView": 1, "componentType": 5121, "count": 3, "type": "SCALAR"}
  ],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                  {"buffer": 0, "byteOffset": 36, "byteLength": 3}],
  "buffers": [{"uri": "small.bin", "byteLength": 40}]
})";

TEST(SceneLoading, GltfHierarchyMaterialsLightsAndCameras) {
  TempDir dir;
  dir.write("small.bin", smallGltfBuffer());
  Scene scene = loadScene(dir.write("small.gltf", kSmallGltf));
  expectConsistent(scene);
  ASSERT_EQ(scene.triangleCount(), 2u) << "the point primitive is skipped";
  ASSERT_EQ(scene.vertices.size(), 6u) << "primitives never share vertices";

  // Child: scale 2, then 90 degrees about +Y (x -> -z), then the parent's translation.
  const glm::vec3 expected[3] = {{10, 0, 0}, {10, 0, -2}, {10, 2, 0}};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(glm::distance(scene.vertices[i].position, expected[i]), 0.0f, 1e-5f) << i;
    EXPECT_NEAR(glm::distance(scene.vertices[i + 3].position, expected[i]), 0.0f, 1e-5f) << i;
  }
  // Generated normals face along +X, the triangle's orientation in the world.
  EXPECT_NEAR(std::abs(scene.vertices[0].normal.x), 1.0f, 1e-5f);

  ASSERT_EQ(scene.materials.size(), 2u) << "a default material for the primitive without one";
  EXPECT_EQ(scene.vertices[0].material, 0u);
  EXPECT_EQ(scene.vertices[3].material, 1u);
  EXPECT_NEAR(scene.materials[0].emissive.r, 4.0f, 1e-6f);
  EXPECT_NEAR(scene.materials[0].emissive.g, 2.0f, 1e-6f);
  EXPECT_EQ(scene.materials[1].emissive, glm::vec3(0.0f));
  EXPECT_EQ(scene.materials[1].baseColorTexture, gpu::kNoTexture);

  ASSERT_EQ(scene.lights.size(), 1u);
  const gpu::Light& spot = scene.lights[0];
  EXPECT_EQ(spot.type, gpu::kLightSpot);
  EXPECT_NEAR(glm::distance(spot.position, glm::vec3(10, 3, 0)), 0.0f, 1e-5f);
  EXPECT_NEAR(spot.direction.y, -1.0f, 1e-5f) << "-Z turned -90 degrees about X points down";
  EXPECT_NEAR(spot.color.g, 5.0f, 1e-5f);
  EXPECT_NEAR(spot.spotCosInner, std::cos(0.2f), 1e-6f);
  EXPECT_NEAR(spot.spotCosOuter, std::cos(0.5f), 1e-6f);
  EXPECT_EQ(spot.range, 0.0f);

  ASSERT_EQ(scene.cameras.size(), 1u);
  const SceneCamera& camera = scene.cameras[0];
  EXPECT_EQ(camera.name, "eye");
  EXPECT_EQ(camera.position, glm::vec3(0, 1, 5));
  EXPECT_EQ(camera.forward, glm::vec3(0, 0, -1));
  EXPECT_FLOAT_EQ(camera.yfov, 0.8f);
  EXPECT_GT(camera.zfar, 100.0f) << "no zfar: an infinite projection";
}

// The same scene packed as a binary glTF: a JSON chunk and a BIN chunk holding the buffer.
std::string packGlb(std::string json, std::string bin) {
  auto pad = [](std::string& chunk, char fill) {
    while (chunk.size() % 4) chunk += fill;
  };
  pad(json, ' ');
  pad(bin, '\0');
  auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  std::string glb = "glTF" + u32(2) + u32(uint32_t(12 + 8 + json.size() + 8 + bin.size()));
  glb += u32(uint32_t(json.size())) + "JSON" + json;
  glb += u32(uint32_t(bin.size())) + std::string("BIN\0", 4) + bin;
  return glb;
}

TEST(SceneLoading, BinaryGltfLoadsLikeTheTextForm) {
  TempDir dir;
  std::string json = kSmallGltf;
  std::string uri = R"("uri": "small.bin", )";
  json.replace(json.find(uri), uri.size(), "");
  Scene fromGlb = loadScene(dir.write("small.glb", packGlb(json, smallGltfBuffer())));
  dir.write("small.bin", smallGltfBuffer());
  Scene fromGltf = loadScene(dir.write("small.gltf", kSmallGltf));
  ASSERT_EQ(fromGlb.vertices.size(), fromGltf.vertices.size());
  for (size_t i = 0; i < fromGlb.vertices.size(); ++i)
    EXPECT_EQ(fromGlb.vertices[i].position, fromGltf.vertices[i].position) << i;
  EXPECT_EQ(fromGlb.cameras.size(), fromGltf.cameras.size());
  EXPECT_EQ(fromGlb.lights.size(), fromGltf.lights.size());
}

TEST(SceneLoading, AccessorsPastTheirBufferAreRejected) {
  TempDir dir;
  dir.write("small.bin", smallGltfBuffer().substr(0, 20));
  std::string gltf = kSmallGltf;
  gltf.replace(gltf.find("\"byteLength\": 40"), 16, "\"byteLength\": 20");
  std::string path = dir.write("short.gltf", gltf);
  sceneErrorOf([&] { loadScene(path); });
}

Scene quadScene(float sizeMetres) {
  // Two triangles sharing a diagonal, uv 0..1 over the quad, no normals.
  Scene scene;
  scene.materials.push_back(
      gpu::Material{glm::vec4(1.0f), glm::vec3(0.0f), 0.0f, 1.0f, gpu::kNoTexture});
  const glm::vec2 corners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (glm::vec2 corner : corners) {
    scene.vertices.push_back(
        gpu::Vertex{glm::vec3(corner * sizeMetres, 0.0f), 0.0f, glm::vec3(0.0f), 0, corner});
  }
  scene.indices = {0, 1, 2, 0, 2, 3};
  return scene;
}

TEST(FinalizeScene, GeneratesNormalsUvScaleBoundsAndADefaultCamera) {
  Scene scene = quadScene(2.0f);
  finalizeScene(scene);
  for (const gpu::Vertex& vertex : scene.vertices) {
    EXPECT_NEAR(vertex.normal.z, 1.0f, 1e-6f);
    EXPECT_NEAR(vertex.uvPerMeter, 0.5f, 1e-6f) << "one texture repeat per 2 m";
  }
  EXPECT_EQ(scene.bounds.min, glm::vec3(0.0f));
  EXPECT_EQ(scene.bounds.max, glm::vec3(2.0f, 2.0f, 0.0f));
  const SceneCamera* camera = scene.findCamera("default");
  ASSERT_NE(camera, nullptr);
  expectValidCamera(*camera);
  ASSERT_TRUE(camera->focusDistance.has_value());
  glm::vec3 toCentre = scene.bounds.center() - camera->position;
  EXPECT_NEAR(glm::dot(glm::normalize(toCentre), camera->forward), 1.0f, 1e-5f);
  EXPECT_NEAR(*camera->focusDistance, glm::length(toCentre), 1e-4f);
}

TEST(FinalizeScene, SmoothNormalsAreAreaWeightedOverSharedVertices) {
  // A roof: a big triangle facing +Z and a small one facing +X share the edge on the y axis.
  Scene scene = quadScene(1.0f);
  scene.vertices = {};
  for (glm::vec3 p :
       {glm::vec3(0, 0, 0), glm::vec3(0, 1, 0), glm::vec3(-3, 0, 0), glm::vec3(0, 0, -1)}) {
    scene.vertices.push_back(gpu::Vertex{p, 0.0f, glm::vec3(0.0f), 0, glm::vec2(0.0f)});
  }
  scene.indices = {0, 1, 2, 0, 3, 1};
  finalizeScene(scene);
  // Areas 1.5 and 0.5: the shared vertices lean three times as much towards +Z as towards +X.
  glm::vec3 shared = scene.vertices[0].normal;
  EXPECT_NEAR(std::abs(shared.z / shared.x), 3.0f, 1e-4f);
  EXPECT_NEAR(std::abs(scene.vertices[2].normal.z), 1.0f, 1e-6f);
  EXPECT_NEAR(std::abs(scene.vertices[3].normal.x), 1.0f, 1e-6f);
}

TEST(FinalizeScene, RejectsBrokenTopology) {
  Scene outOfRange = quadScene(1.0f);
  outOfRange.indices[4] = 4;
  EXPECT_NE(sceneErrorOf([&] { finalizeScene(outOfRange); }).find("out of range"),
            std::string::npos);
  Scene empty = quadScene(1.0f);
  empty.indices.clear();
  sceneErrorOf([&] { finalizeScene(empty); });
  Scene partial = quadScene(1.0f);
  partial.indices.pop_back();
  sceneErrorOf([&] { finalizeScene(partial); });
  Scene badMaterial = quadScene(1.0f);
  badMaterial.vertices[1].material = 3;
  sceneErrorOf([&] { finalizeScene(badMaterial); });
}

Texture solidTexture(uint32_t width, uint32_t height, uint8_t value) {
  Texture texture;
  texture.name = "solid";
  texture.levels.push_back(
      {width, height, std::vector<uint8_t>(size_t{width} * height * 4, value)});
  return texture;
}

TEST(MipChain, OddSizesHalveRoundingDownToOne) {
  struct Case {
    uint32_t width, height;
    std::vector<glm::uvec2> sizes;
  };
  for (const Case& test : {
           Case{5, 3, {{5, 3}, {2, 1}, {1, 1}}},
           Case{7, 1, {{7, 1}, {3, 1}, {1, 1}}},
           Case{1, 1, {{1, 1}}},
           Case{8, 2, {{8, 2}, {4, 1}, {2, 1}, {1, 1}}},
       }) {
    Texture texture = solidTexture(test.width, test.height, 77);
    buildMipChain(texture);
    ASSERT_EQ(texture.levels.size(), test.sizes.size()) << test.width << "x" << test.height;
    for (size_t i = 0; i < test.sizes.size(); ++i) {
      EXPECT_EQ(texture.levels[i].width, test.sizes[i].x);
      EXPECT_EQ(texture.levels[i].height, test.sizes[i].y);
      // A uniform colour survives the sRGB -> linear -> sRGB round trip exactly.
      for (uint8_t value : texture.levels[i].rgba) ASSERT_EQ(value, 77);
    }
  }
}

TEST(MipChain, FiltersInLinearSpace) {
  // Black and white columns average to half the light, which is sRGB 188, not 128.
  Texture texture = solidTexture(2, 1, 0);
  std::fill(texture.levels[0].rgba.begin() + 4, texture.levels[0].rgba.end(), 255);
  buildMipChain(texture);
  ASSERT_EQ(texture.levels.size(), 2u);
  EXPECT_EQ(texture.levels[1].rgba[0], 188);
  EXPECT_EQ(texture.levels[1].rgba[3], 128) << "alpha is linear";
  // An odd row: the last texel takes in all three source texels.
  Texture odd = solidTexture(3, 1, 0);
  std::fill(odd.levels[0].rgba.begin() + 8, odd.levels[0].rgba.end(), 255);
  buildMipChain(odd);
  EXPECT_EQ(odd.levels[1].rgba[0], 156);  // sRGB of 1/3
  sceneErrorOf([] {
    Texture empty;
    buildMipChain(empty);
  });
}

TEST(BuiltinScenes, EveryOneBuildsWithAFocusedDefaultCamera) {
  std::vector<std::string> names = builtinSceneNames();
  ASSERT_FALSE(names.empty());
  EXPECT_EQ(names.front(), "dof");
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    Scene scene = loadScene("builtin:" + name);
    expectConsistent(scene);
    EXPECT_FALSE(scene.lights.empty());
    EXPECT_FALSE(scene.textures.empty());
    const SceneCamera* camera = scene.findCamera("default");
    ASSERT_NE(camera, nullptr);
    ASSERT_TRUE(camera->focusDistance.has_value());
    EXPECT_GT(*camera->focusDistance, camera->znear);
    EXPECT_NEAR(camera->yfov, glm::radians(40.0f), glm::radians(5.0f));
  }
}

TEST(BuiltinScenes, DofFocusesOnTheMiddleGroundWithDepthAndBokehAround) {
  Scene scene = makeBuiltinScene("dof");
  EXPECT_GE(scene.triangleCount(), 5000u);
  EXPECT_LE(scene.triangleCount(), 50000u);
  const SceneCamera& camera = *scene.findCamera("default");
  EXPECT_NEAR(*camera.focusDistance, 4.0f, 0.5f);
  Bvh bvh = buildBvh(scene.vertices, scene.indices);
  std::optional<RayHit> centre = intersect(bvh, camera.position, camera.forward);
  ASSERT_TRUE(centre.has_value());
  EXPECT_NEAR(centre->t, *camera.focusDistance, 0.5f) << "the view's centre is in focus";

  int brightEmitters = 0;
  for (const gpu::Material& material : scene.materials) {
    float radiance =
        glm::max(material.emissive.r, glm::max(material.emissive.g, material.emissive.b));
    brightEmitters += radiance >= 20.0f && radiance <= 60.0f;
  }
  EXPECT_GE(brightEmitters, 1);
}

TEST(BuiltinScenes, WallHasNoDepthEdgeAnywhereInView) {
  Scene scene = makeBuiltinScene("wall");
  const SceneCamera& camera = *scene.findCamera("default");
  EXPECT_FLOAT_EQ(*camera.focusDistance, 3.0f);
  const glm::vec3 normal = scene.vertices[0].normal;
  const float offset = glm::dot(normal, scene.vertices[0].position);
  EXPECT_NEAR(std::abs(glm::dot(normal, camera.forward)), 1.0f, 1e-6f) << "square-on";
  for (const gpu::Vertex& vertex : scene.vertices) {
    ASSERT_NEAR(glm::dot(normal, vertex.position), offset, 1e-5f) << "all triangles coplanar";
    ASSERT_NEAR(glm::dot(normal, vertex.normal), 1.0f, 1e-6f);
  }
  // Rays through the corners of even a very wide view (21:9) all reach the wall.
  Bvh bvh = buildBvh(scene.vertices, scene.indices);
  glm::vec3 right = glm::cross(camera.forward, camera.up);
  float tanHalfY = std::tan(0.5f * camera.yfov), tanHalfX = tanHalfY * 21.0f / 9.0f;
  for (float sx : {-1.0f, 0.0f, 1.0f}) {
    for (float sy : {-1.0f, 0.0f, 1.0f}) {
      glm::vec3 direction = camera.forward + sx * tanHalfX * right + sy * tanHalfY * camera.up;
      std::optional<RayHit> hit = intersect(bvh, camera.position, direction);
      ASSERT_TRUE(hit.has_value()) << sx << " " << sy;
      EXPECT_NEAR(hit->t, 3.0f, 1e-4f) << "depth along the view axis is the same everywhere";
    }
  }
}

TEST(BuiltinScenes, BokehHasATinyBrightLightFarBehindFocus) {
  Scene scene = makeBuiltinScene("bokeh");
  const SceneCamera& camera = *scene.findCamera("default");
  EXPECT_FLOAT_EQ(*camera.focusDistance, 2.0f);
  Bvh bvh = buildBvh(scene.vertices, scene.indices);
  std::optional<RayHit> hit = intersect(bvh, camera.position, camera.forward);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 10.0f, 0.05f);
  uint32_t material = scene.vertices[scene.indices[3 * hit->triangle]].material;
  EXPECT_GE(scene.materials[material].emissive.g, 100.0f);
  // Just off the light, the ray reaches the dark backdrop at 20 m.
  std::optional<RayHit> beside =
      intersect(bvh, camera.position, camera.forward + glm::vec3(0.01f, 0.0f, 0.0f));
  ASSERT_TRUE(beside.has_value());
  EXPECT_NEAR(beside->t, 20.0f, 0.1f);
}

}  // namespace
}  // namespace hdof
