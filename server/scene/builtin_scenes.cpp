// The built-in scenes: procedural test scenes for depth of field, with light levels of the same
// magnitude as the living room (sun about 3 lux, point lights tens of candela).
#include "scene/procedural.h"
#include "scene/scene.h"

#include <glm/gtc/constants.hpp>

namespace hdof {

namespace {

using namespace procedural;

constexpr uint32_t kTextureSize = 512;
constexpr float kDefaultYfov = glm::radians(40.0f);

SceneCamera lookAt(const glm::vec3& eye, const glm::vec3& target, float focusDistance) {
  SceneCamera camera;
  camera.name = "default";
  camera.position = eye;
  camera.forward = glm::normalize(target - eye);
  glm::vec3 right = glm::normalize(glm::cross(camera.forward, glm::vec3(0.0f, 1.0f, 0.0f)));
  camera.up = glm::cross(right, camera.forward);
  camera.yfov = kDefaultYfov;
  camera.znear = 0.05f;
  camera.zfar = 200.0f;
  camera.focusDistance = focusDistance;
  return camera;
}

gpu::Light sunLight(const glm::vec3& travelDirection, float illuminance) {
  gpu::Light light{};
  light.type = gpu::kLightDirectional;
  light.direction = glm::normalize(travelDirection);
  light.color = glm::vec3(1.0f, 0.95f, 0.85f) * illuminance;
  light.spotCosInner = light.spotCosOuter = -1.0f;
  return light;
}

gpu::Light pointLight(const glm::vec3& position, const glm::vec3& color, float candela) {
  gpu::Light light{};
  light.type = gpu::kLightPoint;
  light.position = position;
  light.direction = glm::vec3(0.0f, -1.0f, 0.0f);
  light.color = color * candela;
  light.spotCosInner = light.spotCosOuter = -1.0f;
  return light;
}

uint32_t addEmitter(Scene& scene, const glm::vec3& radiance) {
  return addMaterial(scene, makeMaterial(glm::vec3(0.0f), 1.0f, 0.0f, gpu::kNoTexture, radiance));
}

uint32_t addTextured(Scene& scene, Texture texture, float roughness) {
  uint32_t index = addTexture(scene, std::move(texture));
  return addMaterial(scene, makeMaterial(glm::vec3(1.0f), roughness, 0.0f, index));
}

// A railing at 0.8 m, foreground objects at 1-2 m, a fence and poles at 3-4 m, textured crates,
// shiny spheres and columns around the focus plane at 4 m and behind it, a brick wall at 12 m, and
// small bright lights at every depth for bokeh.
Scene makeDofScene() {
  Scene scene;
  scene.name = "dof";
  uint32_t bricks = addTextured(scene, bricksTexture(kTextureSize), 0.9f);
  uint32_t tiles = addTextured(scene, tilesTexture(kTextureSize), 0.7f);
  uint32_t planks = addTextured(scene, planksTexture(kTextureSize), 0.6f);
  uint32_t stone = addTextured(scene, stoneTexture(kTextureSize), 0.4f);
  uint32_t checker = addTextured(scene, checkerTexture(kTextureSize), 0.5f);
  uint32_t chrome = addMaterial(scene, makeMaterial(glm::vec3(0.95f), 0.04f, 1.0f));
  uint32_t gold = addMaterial(scene, makeMaterial(glm::vec3(1.0f, 0.77f, 0.34f), 0.12f, 1.0f));
  uint32_t redGloss = addMaterial(scene, makeMaterial(glm::vec3(0.6f, 0.04f, 0.03f), 0.08f));
  uint32_t paint = addMaterial(scene, makeMaterial(glm::vec3(0.75f, 0.75f, 0.7f), 0.5f));
  uint32_t darkMetal = addMaterial(scene, makeMaterial(glm::vec3(0.2f), 0.3f, 1.0f));

  // Ground and the far wall.
  addQuad(scene, {-15.0f, 0.0f, 3.0f}, {30.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -33.0f}, {tiles, 0.5f}, 8);
  addBox(scene, {0.0f, 3.0f, -12.25f}, {15.0f, 3.0f, 0.25f}, 0.0f, {bricks, 1.0f});
  addBox(scene, {0.0f, 6.05f, -12.2f}, {15.2f, 0.08f, 0.35f}, 0.0f, {stone, 1.0f});

  // Middle ground: the crate the camera focuses on, more crates, columns, shiny spheres.
  addBox(scene, {0.35f, 0.45f, -4.45f}, glm::vec3(0.45f), 0.4f, {checker, 1.0f});
  addBox(scene, {-2.2f, 0.5f, -6.0f}, glm::vec3(0.5f), -0.3f, {planks, 1.0f});
  addBox(scene, {-2.1f, 1.35f, -6.1f}, glm::vec3(0.35f), 0.25f, {planks, 1.0f});
  addBox(scene, {3.2f, 0.6f, -8.5f}, {0.8f, 0.6f, 0.6f}, -0.5f, {planks, 1.0f});
  for (glm::vec3 base : {glm::vec3(-4.0f, 0.0f, -8.0f), glm::vec3(2.4f, 0.0f, -6.6f),
                         glm::vec3(5.2f, 0.0f, -10.0f), glm::vec3(-1.0f, 0.0f, -10.5f)}) {
    addCylinder(scene, base, 0.3f, 4.2f, {stone, 1.0f}, 48);
  }
  addSphere(scene, {2.2f, 0.55f, -9.0f}, 0.55f, {chrome, 1.0f}, 32);
  addSphere(scene, {-0.9f, 0.3f, -4.6f}, 0.3f, {gold, 1.0f}, 32);
  addSphere(scene, {0.35f, 1.1f, -4.45f}, 0.2f, {redGloss, 1.0f}, 24);

  // Thin features: a picket fence on the left and a receding row of poles on the right.
  for (int post = 0; post < 13; ++post) {
    addCylinder(scene, {-3.6f + 0.22f * static_cast<float>(post), 0.0f, -3.5f}, 0.022f, 1.0f,
                {paint, 1.0f}, 12);
  }
  for (float railHeight : {0.35f, 0.85f}) {
    addBox(scene, {-2.28f, railHeight, -3.52f}, {1.4f, 0.025f, 0.012f}, 0.0f, {paint, 1.0f});
  }
  for (int pole = 0; pole < 5; ++pole) {
    float k = static_cast<float>(pole);
    addCylinder(scene, {1.4f + 0.35f * k, 0.0f, -3.0f - 0.4f * k}, 0.03f, 2.2f, {darkMetal, 1.0f},
                12);
  }

  // Foreground: a post crossing the whole view, a glossy ball on a stand, a crate cut by the frame.
  addBox(scene, {-0.35f, 1.1f, -1.4f}, {0.04f, 1.1f, 0.04f}, 0.2f, {planks, 2.0f});
  addCylinder(scene, {0.45f, 0.0f, -1.6f}, 0.012f, 0.74f, {darkMetal, 1.0f}, 12);
  addSphere(scene, {0.45f, 0.85f, -1.6f}, 0.12f, {chrome, 1.0f}, 32);
  addBox(scene, {0.75f, 0.3f, -2.3f}, glm::vec3(0.3f), -0.2f, {planks, 1.0f});

  // Up close (0.75-0.8 m): a railing across the lower left, strongly blurred at any aperture:
  // the partial-occlusion case, where the background must show through its blurred edges.
  addBox(scene, {-0.55f, 0.95f, -0.8f}, {0.45f, 0.035f, 0.05f}, 0.0f, {planks, 1.0f});
  addBox(scene, {-0.2f, 0.5f, -0.75f}, {0.04f, 0.5f, 0.04f}, 0.0f, {planks, 1.0f});

  // Small bright lights for bokeh: a string along the wall, some in the middle, two up close.
  uint32_t warmLight = addEmitter(scene, glm::vec3(40.0f, 30.0f, 18.0f));
  uint32_t coolLight = addEmitter(scene, glm::vec3(20.0f, 30.0f, 50.0f));
  for (int bulb = 0; bulb < 16; ++bulb) {
    float x = -6.0f + 0.8f * static_cast<float>(bulb);
    float sag = 0.15f * std::cos(static_cast<float>(bulb) * 0.8f);
    addSphere(scene, {x, 2.3f + sag, -11.8f}, 0.035f, {bulb % 3 == 0 ? coolLight : warmLight, 1.0f},
              8);
  }
  addSphere(scene, {-1.0f, 2.0f, -7.0f}, 0.04f, {coolLight, 1.0f}, 8);
  addSphere(scene, {3.5f, 1.6f, -6.0f}, 0.04f, {warmLight, 1.0f}, 8);
  addSphere(scene, {-2.6f, 1.9f, -5.5f}, 0.04f, {warmLight, 1.0f}, 8);
  addSphere(scene, {-0.7f, 1.45f, -1.8f}, 0.02f, {warmLight, 1.0f}, 8);
  addSphere(scene, {0.9f, 1.55f, -2.0f}, 0.02f, {coolLight, 1.0f}, 8);

  scene.lights.push_back(sunLight({0.35f, -0.7f, -0.6f}, 3.0f));
  scene.lights.push_back(pointLight({0.5f, 2.6f, -3.0f}, {1.0f, 0.85f, 0.7f}, 20.0f));
  scene.lights.push_back(pointLight({-2.5f, 2.2f, -8.0f}, {0.8f, 0.9f, 1.0f}, 12.0f));
  scene.cameras.push_back(lookAt({0.0f, 1.25f, 0.0f}, {0.15f, 0.55f, -4.45f}, 4.0f));
  finalizeScene(scene);
  return scene;
}

// One textured plane square-on to the camera and larger than any view of it: no depth edges.
Scene makeWallScene() {
  Scene scene;
  scene.name = "wall";
  uint32_t bricks = addTextured(scene, bricksTexture(kTextureSize), 0.9f);
  addQuad(scene, {-10.0f, -8.5f, -3.0f}, {20.0f, 0.0f, 0.0f}, {0.0f, 20.0f, 0.0f}, {bricks, 1.0f},
          16);
  scene.lights.push_back(sunLight({0.3f, -0.5f, -0.8f}, 3.0f));
  scene.lights.push_back(pointLight({0.8f, 2.2f, -1.5f}, {1.0f, 0.9f, 0.8f}, 8.0f));
  scene.cameras.push_back(lookAt({0.0f, 1.5f, 0.0f}, {0.0f, 1.5f, -3.0f}, 3.0f));
  finalizeScene(scene);
  return scene;
}

// A tiny, very bright light far behind the focus plane, in front of a dark backdrop: the far-field
// bokeh disc in isolation.
Scene makeBokehScene() {
  Scene scene;
  scene.name = "bokeh";
  uint32_t stoneIndex = addTexture(scene, stoneTexture(kTextureSize));
  uint32_t backdrop = addMaterial(scene, makeMaterial(glm::vec3(0.04f), 1.0f, 0.0f, stoneIndex));
  uint32_t light = addEmitter(scene, glm::vec3(200.0f));
  addQuad(scene, {-30.0f, -28.5f, -20.0f}, {60.0f, 0.0f, 0.0f}, {0.0f, 60.0f, 0.0f},
          {backdrop, 0.5f}, 4);
  addSphere(scene, {0.0f, 1.5f, -10.0f}, 0.02f, {light, 1.0f}, 12);
  scene.skyColor = glm::vec3(0.01f);
  scene.groundColor = glm::vec3(0.005f);
  // A dim sun, so light lists are never empty.
  scene.lights.push_back(sunLight({0.2f, -0.5f, -0.8f}, 0.3f));
  scene.cameras.push_back(lookAt({0.0f, 1.5f, 0.0f}, {0.0f, 1.5f, -10.0f}, 2.0f));
  finalizeScene(scene);
  return scene;
}

struct BuiltinScene {
  const char* name;
  Scene (*make)();
};

constexpr BuiltinScene kBuiltinScenes[] = {
    {"dof", makeDofScene},
    {"wall", makeWallScene},
    {"bokeh", makeBokehScene},
};

}  // namespace

std::vector<std::string> builtinSceneNames() {
  std::vector<std::string> names;
  for (const BuiltinScene& scene : kBuiltinScenes) names.emplace_back(scene.name);
  return names;
}

Scene makeBuiltinScene(const std::string& name) {
  for (const BuiltinScene& scene : kBuiltinScenes) {
    if (name == scene.name) return scene.make();
  }
  std::string known;
  for (const std::string& builtin : builtinSceneNames())
    known += (known.empty() ? "" : ", ") + builtin;
  throw SceneError("unknown built-in scene '" + name + "': choose one of " + known);
}

}  // namespace hdof
