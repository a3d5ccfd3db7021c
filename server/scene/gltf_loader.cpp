#include "scene/scene.h"

#include <tiny_gltf.h>

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cctype>
#include <cstring>
#include <iostream>
#include <map>
#include <set>

namespace hdof {

namespace {

const std::set<std::string> kSupportedRequiredExtensions = {"KHR_lights_punctual",
                                                            "KHR_materials_emissive_strength"};

std::string firstLine(const std::string& text) {
  size_t start = text.find_first_not_of(" \t\r\n");
  if (start == std::string::npos) return "unknown error";
  size_t end = text.find_first_of("\r\n", start);
  return text.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

glm::mat4 localTransform(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) {
    glm::dmat4 matrix = glm::make_mat4(node.matrix.data());  // column-major, as glTF stores it
    return glm::mat4(matrix);
  }
  glm::mat4 transform(1.0f);
  if (node.translation.size() == 3) {
    transform = glm::translate(transform, glm::vec3(glm::make_vec3(node.translation.data())));
  }
  if (node.rotation.size() == 4) {
    const std::vector<double>& r = node.rotation;  // x, y, z, w
    glm::quat rotation(static_cast<float>(r[3]), static_cast<float>(r[0]), static_cast<float>(r[1]),
                       static_cast<float>(r[2]));
    transform *= glm::mat4_cast(glm::normalize(rotation));
  }
  if (node.scale.size() == 3) {
    transform = glm::scale(transform, glm::vec3(glm::make_vec3(node.scale.data())));
  }
  return transform;
}

// One accessor's elements as floats, whatever its component type (normalized integers map to
// [0, 1] or [-1, 1] as glTF defines), after checking that it stays inside its buffer.
class AccessorReader {
 public:
  AccessorReader(const tinygltf::Model& model, int accessorIndex, const std::string& what) {
    auto fail = [&](const std::string& problem) {
      throw SceneError(what + " (accessor " + std::to_string(accessorIndex) + "): " + problem);
    };
    if (accessorIndex < 0 || accessorIndex >= static_cast<int>(model.accessors.size())) {
      fail("no such accessor");
    }
    const tinygltf::Accessor& accessor = model.accessors[accessorIndex];
    if (accessor.sparse.isSparse) fail("sparse accessors are not supported");
    count_ = accessor.count;
    componentType_ = accessor.componentType;
    normalized_ = accessor.normalized;
    components_ = tinygltf::GetNumComponentsInType(accessor.type);
    int componentSize = tinygltf::GetComponentSizeInBytes(accessor.componentType);
    if (components_ <= 0 || componentSize <= 0) fail("unsupported element type");
    componentSize_ = static_cast<size_t>(componentSize);
    if (count_ == 0) return;
    if (accessor.bufferView < 0 ||
        accessor.bufferView >= static_cast<int>(model.bufferViews.size())) {
      fail("has no buffer view");
    }
    const tinygltf::BufferView& view = model.bufferViews[accessor.bufferView];
    if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size())) {
      fail("has no buffer");
    }
    const std::vector<unsigned char>& buffer = model.buffers[view.buffer].data;
    int stride = accessor.ByteStride(view);
    if (stride <= 0) fail("invalid byte stride");
    stride_ = static_cast<size_t>(stride);
    size_t start = view.byteOffset + accessor.byteOffset;
    size_t end = start + (count_ - 1) * stride_ + components_ * componentSize_;
    if (end > view.byteOffset + view.byteLength || end > buffer.size()) {
      fail("reads past the end of its buffer");
    }
    data_ = buffer.data() + start;
  }

  size_t count() const { return count_; }
  bool holdsIndices() const {
    return components_ == 1 && (componentType_ == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                componentType_ == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
                                componentType_ == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
  }
  int components() const { return components_; }

  float component(size_t element, int component) const {
    const unsigned char* p = data_ + element * stride_ + component * componentSize_;
    switch (componentType_) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return load<float>(p);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return scaled(load<uint8_t>(p), 255.0f);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return scaled(load<uint16_t>(p), 65535.0f);
      case TINYGLTF_COMPONENT_TYPE_BYTE:
        return signedScaled(load<int8_t>(p), 127.0f);
      case TINYGLTF_COMPONENT_TYPE_SHORT:
        return signedScaled(load<int16_t>(p), 32767.0f);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        return static_cast<float>(load<uint32_t>(p));
      default:
        return 0.0f;
    }
  }

  uint32_t index(size_t element) const {
    const unsigned char* p = data_ + element * stride_;
    switch (componentType_) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return load<uint8_t>(p);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return load<uint16_t>(p);
      default:
        return load<uint32_t>(p);
    }
  }

  glm::vec2 vec2(size_t element) const { return {component(element, 0), component(element, 1)}; }
  glm::vec3 vec3(size_t element) const {
    return {component(element, 0), component(element, 1), component(element, 2)};
  }

 private:
  template <typename T>
  static T load(const unsigned char* p) {
    T value;
    std::memcpy(&value, p, sizeof(T));  // glTF data need not be aligned
    return value;
  }
  float scaled(float value, float maximum) const { return normalized_ ? value / maximum : value; }
  float signedScaled(float value, float maximum) const {
    return normalized_ ? std::max(value / maximum, -1.0f) : value;
  }

  const unsigned char* data_ = nullptr;
  size_t count_ = 0, stride_ = 0, componentSize_ = 0;
  int componentType_ = 0, components_ = 0;
  bool normalized_ = false;
};

// Image data as tinygltf decoded it (any channel count, 8 or 16 bits) to RGBA8, sRGB as stored.
Texture decodeTexture(const tinygltf::Image& image, const std::string& name) {
  if (image.width <= 0 || image.height <= 0 || image.component < 1 || image.component > 4 ||
      (image.bits != 8 && image.bits != 16)) {
    throw SceneError("image '" + name + "' could not be decoded");
  }
  size_t pixels = size_t(image.width) * size_t(image.height);
  size_t bytesPerChannel = image.bits / 8;
  if (image.image.size() < pixels * image.component * bytesPerChannel) {
    throw SceneError("image '" + name + "' has less data than its size says");
  }
  auto channel = [&](size_t pixel, int c) -> uint8_t {
    size_t offset = (pixel * image.component + c) * bytesPerChannel;
    if (bytesPerChannel == 1) return image.image[offset];
    uint16_t value;
    std::memcpy(&value, &image.image[offset], 2);
    return static_cast<uint8_t>(value >> 8);
  };
  Texture texture;
  texture.name = name;
  Texture::Level& level = texture.levels.emplace_back();
  level.width = static_cast<uint32_t>(image.width);
  level.height = static_cast<uint32_t>(image.height);
  level.rgba.resize(pixels * 4);
  for (size_t i = 0; i < pixels; ++i) {
    uint8_t* out = &level.rgba[i * 4];
    bool grey = image.component <= 2;  // grey or grey + alpha
    out[0] = channel(i, 0);
    out[1] = grey ? out[0] : channel(i, 1);
    out[2] = grey ? out[0] : channel(i, 2);
    out[3] = image.component == 2 ? channel(i, 1) : image.component == 4 ? channel(i, 3) : 255;
  }
  buildMipChain(texture);
  return texture;
}

class GltfSceneBuilder {
 public:
  GltfSceneBuilder(const tinygltf::Model& model, const std::string& path)
      : model_(model), path_(path) {}

  Scene build() {
    size_t slash = path_.find_last_of("/\\");
    std::string fileName = slash == std::string::npos ? path_ : path_.substr(slash + 1);
    scene_.name = fileName.substr(0, fileName.find_last_of('.'));
    for (size_t i = 0; i < model_.materials.size(); ++i) {
      scene_.materials.push_back(convertMaterial(model_.materials[i]));
    }
    for (int root : rootNodes()) visitNode(root, glm::mat4(1.0f), 0);
    finalizeScene(scene_);
    return std::move(scene_);
  }

 private:
  std::vector<int> rootNodes() const {
    int sceneIndex = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    if (sceneIndex < static_cast<int>(model_.scenes.size())) return model_.scenes[sceneIndex].nodes;
    // No scene at all: every node that is nobody's child is a root.
    std::vector<bool> isChild(model_.nodes.size());
    for (const tinygltf::Node& node : model_.nodes) {
      for (int child : node.children) {
        if (child >= 0 && child < static_cast<int>(isChild.size())) isChild[child] = true;
      }
    }
    std::vector<int> roots;
    for (size_t i = 0; i < isChild.size(); ++i) {
      if (!isChild[i]) roots.push_back(static_cast<int>(i));
    }
    return roots;
  }

  void visitNode(int nodeIndex, const glm::mat4& parentTransform, int depth) {
    if (nodeIndex < 0 || nodeIndex >= static_cast<int>(model_.nodes.size())) {
      throw SceneError("node " + std::to_string(nodeIndex) + " does not exist");
    }
    // A valid glTF node hierarchy is a forest; this deep it can only be a cycle.
    if (depth > 1000) {
      throw SceneError("the node hierarchy has a cycle");
    }
    const tinygltf::Node& node = model_.nodes[nodeIndex];
    glm::mat4 world = parentTransform * localTransform(node);
    if (node.mesh >= 0 && node.mesh < static_cast<int>(model_.meshes.size())) {
      addMesh(node.mesh, world);
    }
    if (node.camera >= 0 && node.camera < static_cast<int>(model_.cameras.size())) {
      addCamera(model_.cameras[node.camera], node, world);
    }
    auto lightExtension = node.extensions.find("KHR_lights_punctual");
    if (lightExtension != node.extensions.end() && lightExtension->second.Has("light")) {
      int light = lightExtension->second.Get("light").GetNumberAsInt();
      if (light >= 0 && light < static_cast<int>(model_.lights.size())) {
        addLight(model_.lights[light], world);
      }
    }
    for (int child : node.children) visitNode(child, world, depth + 1);
  }

  void addMesh(int meshIndex, const glm::mat4& world) {
    const tinygltf::Mesh& mesh = model_.meshes[meshIndex];
    std::string meshName =
        "mesh " + std::to_string(meshIndex) + (mesh.name.empty() ? "" : " '" + mesh.name + "'");
    glm::mat3 normalTransform = glm::inverseTranspose(glm::mat3(world));
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      const tinygltf::Primitive& primitive = mesh.primitives[p];
      std::string what = meshName + " primitive " + std::to_string(p);
      if (primitive.mode != TINYGLTF_MODE_TRIANGLES) {
        warn(what + ": skipped (only triangle lists are supported)");
        continue;
      }
      auto position = primitive.attributes.find("POSITION");
      if (position == primitive.attributes.end()) {
        warn(what + ": skipped (no POSITION)");
        continue;
      }
      AccessorReader positions(model_, position->second, what + " POSITION");
      std::optional<AccessorReader> normals, uvs;
      if (auto it = primitive.attributes.find("NORMAL"); it != primitive.attributes.end()) {
        normals.emplace(model_, it->second, what + " NORMAL");
      }
      if (auto it = primitive.attributes.find("TEXCOORD_0"); it != primitive.attributes.end()) {
        uvs.emplace(model_, it->second, what + " TEXCOORD_0");
      }
      size_t vertexCount = positions.count();
      if (positions.components() < 3 ||
          (normals && (normals->count() != vertexCount || normals->components() < 3)) ||
          (uvs && (uvs->count() != vertexCount || uvs->components() < 2))) {
        throw SceneError(what + ": vertex attributes of different lengths or types");
      }
      uint32_t material =
          primitive.material >= 0 && primitive.material < static_cast<int>(model_.materials.size())
              ? static_cast<uint32_t>(primitive.material)
              : defaultMaterial();

      uint32_t firstVertex = static_cast<uint32_t>(scene_.vertices.size());
      for (size_t i = 0; i < vertexCount; ++i) {
        gpu::Vertex vertex{};
        vertex.position = glm::vec3(world * glm::vec4(positions.vec3(i), 1.0f));
        // Missing normals stay zero: finalizeScene generates them.
        if (normals) vertex.normal = normalTransform * normals->vec3(i);
        if (uvs) vertex.uv = uvs->vec2(i);
        vertex.material = material;
        scene_.vertices.push_back(vertex);
      }

      if (primitive.indices >= 0) {
        AccessorReader indices(model_, primitive.indices, what + " indices");
        if (!indices.holdsIndices()) throw SceneError(what + ": indices are not unsigned integers");
        for (size_t i = 0; i + 2 < indices.count(); i += 3) {
          for (size_t k = 0; k < 3; ++k) {
            uint32_t index = indices.index(i + k);
            if (index >= vertexCount) throw SceneError(what + ": vertex index out of range");
            scene_.indices.push_back(firstVertex + index);
          }
        }
      } else {
        for (size_t i = 0; i + 2 < vertexCount; i += 3) {
          for (uint32_t k = 0; k < 3; ++k) {
            scene_.indices.push_back(firstVertex + static_cast<uint32_t>(i) + k);
          }
        }
      }
    }
  }

  uint32_t defaultMaterial() {
    if (!defaultMaterial_) {
      defaultMaterial_ = static_cast<uint32_t>(scene_.materials.size());
      scene_.materials.push_back(gpu::Material{glm::vec4(0.5f, 0.5f, 0.5f, 1.0f), glm::vec3(0.0f),
                                               0.0f, 0.8f, gpu::kNoTexture});
    }
    return *defaultMaterial_;
  }

  gpu::Material convertMaterial(const tinygltf::Material& source) {
    const tinygltf::PbrMetallicRoughness& pbr = source.pbrMetallicRoughness;
    gpu::Material material{};
    for (int c = 0; c < 4 && c < static_cast<int>(pbr.baseColorFactor.size()); ++c) {
      material.baseColor[c] = static_cast<float>(pbr.baseColorFactor[c]);
    }
    material.metallic = static_cast<float>(pbr.metallicFactor);
    material.roughness = static_cast<float>(pbr.roughnessFactor);
    float emissiveStrength = 1.0f;
    if (auto it = source.extensions.find("KHR_materials_emissive_strength");
        it != source.extensions.end() && it->second.Has("emissiveStrength")) {
      emissiveStrength = static_cast<float>(it->second.Get("emissiveStrength").GetNumberAsDouble());
    }
    for (int c = 0; c < 3 && c < static_cast<int>(source.emissiveFactor.size()); ++c) {
      material.emissive[c] = static_cast<float>(source.emissiveFactor[c]) * emissiveStrength;
    }
    material.baseColorTexture = textureForMaterial(source);
    return material;
  }

  uint32_t textureForMaterial(const tinygltf::Material& material) {
    const tinygltf::TextureInfo& info = material.pbrMetallicRoughness.baseColorTexture;
    if (info.index < 0 || info.index >= static_cast<int>(model_.textures.size())) {
      return gpu::kNoTexture;
    }
    if (info.texCoord != 0) {
      warn("material '" + material.name + "': base colour texture uses TEXCOORD_" +
           std::to_string(info.texCoord) + "; TEXCOORD_0 is used instead");
    }
    int image = model_.textures[info.index].source;
    if (image < 0 || image >= static_cast<int>(model_.images.size())) return gpu::kNoTexture;
    if (auto known = textureOfImage_.find(image); known != textureOfImage_.end()) {
      return known->second;
    }
    if (scene_.textures.size() >= gpu::kMaxTextureLayers) {
      warn("more than " + std::to_string(gpu::kMaxTextureLayers) + " textures; material '" +
           material.name + "' is drawn untextured");
      return gpu::kNoTexture;
    }
    const tinygltf::Image& source = model_.images[image];
    std::string name = !source.name.empty()  ? source.name
                       : !source.uri.empty() ? source.uri
                                             : "image " + std::to_string(image);
    uint32_t textureIndex = static_cast<uint32_t>(scene_.textures.size());
    scene_.textures.push_back(decodeTexture(source, name));
    textureOfImage_[image] = textureIndex;
    return textureIndex;
  }

  void addCamera(const tinygltf::Camera& source, const tinygltf::Node& node,
                 const glm::mat4& world) {
    if (source.type != "perspective") {
      warn("camera '" + source.name + "' skipped (only perspective cameras are supported)");
      return;
    }
    SceneCamera camera;
    camera.name = !source.name.empty() ? source.name
                  : !node.name.empty() ? node.name
                                       : "camera " + std::to_string(scene_.cameras.size());
    camera.position = glm::vec3(world[3]);
    camera.forward = glm::normalize(-glm::vec3(world[2]));
    glm::vec3 up = glm::vec3(world[1]);
    camera.up = glm::normalize(up - glm::dot(up, camera.forward) * camera.forward);
    camera.yfov = static_cast<float>(source.perspective.yfov);
    camera.znear = static_cast<float>(source.perspective.znear);
    // glTF leaves zfar out for an infinite projection.
    if (source.perspective.zfar > 0.0) camera.zfar = static_cast<float>(source.perspective.zfar);
    scene_.cameras.push_back(camera);
  }

  void addLight(const tinygltf::Light& source, const glm::mat4& world) {
    gpu::Light light{};
    if (source.type == "directional") {
      light.type = gpu::kLightDirectional;
    } else if (source.type == "point") {
      light.type = gpu::kLightPoint;
    } else if (source.type == "spot") {
      light.type = gpu::kLightSpot;
    } else {
      warn("light '" + source.name + "' of unknown type '" + source.type + "' skipped");
      return;
    }
    light.position = glm::vec3(world[3]);
    light.direction = glm::normalize(-glm::vec3(world[2]));
    glm::vec3 color(1.0f);
    for (int c = 0; c < 3 && c < static_cast<int>(source.color.size()); ++c) {
      color[c] = static_cast<float>(source.color[c]);
    }
    light.color = color * static_cast<float>(source.intensity);
    light.range = static_cast<float>(source.range);
    // Non-spot lights get a cone that covers every direction.
    bool spot = light.type == gpu::kLightSpot;
    light.spotCosInner = spot ? static_cast<float>(std::cos(source.spot.innerConeAngle)) : -1.0f;
    light.spotCosOuter = spot ? static_cast<float>(std::cos(source.spot.outerConeAngle)) : -1.0f;
    scene_.lights.push_back(light);
  }

  void warn(const std::string& message) const {
    std::cerr << "warning: scene '" << path_ << "': " << message << "\n";
  }

  const tinygltf::Model& model_;
  std::string path_;
  Scene scene_;
  std::optional<uint32_t> defaultMaterial_;
  std::map<int, uint32_t> textureOfImage_;
};

}  // namespace

Scene loadGltfScene(const std::string& path) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warning;
  std::string suffix = path.size() >= 4 ? path.substr(path.size() - 4) : "";
  for (char& c : suffix) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  bool binary = suffix == ".glb";
  bool loaded = binary ? loader.LoadBinaryFromFile(&model, &error, &warning, path)
                       : loader.LoadASCIIFromFile(&model, &error, &warning, path);
  if (!loaded) throw SceneError("cannot read scene '" + path + "': " + firstLine(error));
  if (!warning.empty())
    std::cerr << "warning: scene '" << path << "': " << firstLine(warning) << "\n";
  for (const std::string& required : model.extensionsRequired) {
    if (!kSupportedRequiredExtensions.contains(required)) {
      throw SceneError("cannot load scene '" + path + "': it requires the glTF extension " +
                       required + ", which is not supported");
    }
  }
  try {
    return GltfSceneBuilder(model, path).build();
  } catch (const SceneError& e) {
    throw SceneError("cannot load scene '" + path + "': " + e.what());
  }
}

}  // namespace hdof
