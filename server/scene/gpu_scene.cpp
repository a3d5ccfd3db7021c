#include "scene/gpu_scene.h"

#include "scene/gpu_bvh.h"

#include <stb_image_resize.h>

#include <algorithm>
#include <cstring>

namespace hdof {
namespace {

// Resamples every texture to one square power-of-two size (sRGB-aware) with a full mip chain,
// and uploads them as the layers of one array image.
gpu::Image uploadTextureArray(const gpu::Context& context, const std::vector<Texture>& textures) {
  uint32_t side = 1;
  for (const Texture& t : textures)
    while (side < std::max(t.levels[0].width, t.levels[0].height) &&
           side < gpu::kMaxTextureLayerSize)
      side *= 2;
  std::vector<Texture> layers;
  if (textures.empty()) layers.push_back(Texture{"white", {{1, 1, {255, 255, 255, 255}}}});
  for (const Texture& t : textures) {
    Texture layer{t.name, {{side, side, std::vector<uint8_t>(size_t(side) * side * 4)}}};
    const Texture::Level& source = t.levels[0];
    if (!stbir_resize_uint8_srgb(source.rgba.data(), int(source.width), int(source.height), 0,
                                 layer.levels[0].rgba.data(), int(side), int(side), 0, 4, 3, 0))
      throw SceneError("cannot resample texture '" + t.name + "'");
    buildMipChain(layer);
    layers.push_back(std::move(layer));
  }

  gpu::ImageDesc desc;
  desc.width = desc.height = layers[0].levels[0].width;
  desc.mipLevels = static_cast<uint32_t>(layers[0].levels.size());
  desc.layers = static_cast<uint32_t>(layers.size());
  desc.arrayView = true;
  desc.format = VK_FORMAT_R8G8B8A8_SRGB;
  desc.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  gpu::Image image(context, desc, "scene textures");

  VkDeviceSize total = 0;
  for (const Texture& layer : layers)
    for (const auto& level : layer.levels) total += level.rgba.size();
  gpu::Buffer staging(context, total, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, gpu::MemoryUse::Upload,
                      "texture staging");
  std::vector<VkBufferImageCopy> regions;
  VkDeviceSize offset = 0;
  for (uint32_t layer = 0; layer < layers.size(); ++layer) {
    for (uint32_t mip = 0; mip < layers[layer].levels.size(); ++mip) {
      const Texture::Level& level = layers[layer].levels[mip];
      std::memcpy(static_cast<uint8_t*>(staging.mapped()) + offset, level.rgba.data(),
                  level.rgba.size());
      VkBufferImageCopy region{};
      region.bufferOffset = offset;
      region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, mip, layer, 1};
      region.imageExtent = {level.width, level.height, 1};
      regions.push_back(region);
      offset += level.rgba.size();
    }
  }
  context.submitAndWait([&](VkCommandBuffer cmd) {
    gpu::transitionImage(cmd, image.get(), VK_IMAGE_LAYOUT_UNDEFINED,
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    vkCmdCopyBufferToImage(cmd, staging.get(), image.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                           static_cast<uint32_t>(regions.size()), regions.data());
    gpu::transitionImage(cmd, image.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                         VK_ACCESS_SHADER_READ_BIT);
  });
  return image;
}

// Uploads BVH data as a uniform texel buffer of RGBA32UI texels, the way lib/bvh_traverse.glsl
// reads it.
std::vector<gpu::PackedVertex> packVertices(const Scene& scene) {
  std::vector<gpu::PackedVertex> packed;
  packed.reserve(scene.vertices.size());
  for (const gpu::Vertex& v : scene.vertices)
    packed.push_back({v.position, v.uvPerMeter, v.uv, gpu::packNormal(v.normal), v.material});
  return packed;
}

std::vector<glm::uvec4> packTriangles(const Scene& scene) {
  std::vector<glm::uvec4> packed;
  packed.reserve(scene.triangleCount());
  for (size_t i = 0; i < scene.indices.size(); i += 3) {
    uint32_t a = scene.indices[i];
    packed.emplace_back(a, scene.indices[i + 1], scene.indices[i + 2], scene.vertices[a].material);
  }
  return packed;
}

std::vector<gpu::PackedMaterial> packMaterials(const Scene& scene) {
  std::vector<gpu::PackedMaterial> packed;
  for (const gpu::Material& m : scene.materials)
    packed.push_back({m.baseColor, m.emissive, m.metallic, m.roughness, m.baseColorTexture, {}});
  return packed;
}

template <typename T>
gpu::Buffer uploadTexels(const gpu::Context& context, const std::vector<T>& items,
                         const std::string& name) {
  static_assert(sizeof(T) % sizeof(glm::uvec4) == 0);
  size_t texels = items.size() * (sizeof(T) / sizeof(glm::uvec4));
  uint32_t limit = context.properties().limits.maxTexelBufferElements;
  if (texels > limit)
    throw SceneError("the scene is too large for this device: " + name + " take " +
                     std::to_string(texels) + " texels, at most " + std::to_string(limit) +
                     " are supported");
  return gpu::createBufferWithData(context, std::span(items),
                                   VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT, name);
}

auto createTexelView(const gpu::Context& context, const gpu::Buffer& buffer,
                     const std::string& name) {
  VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
  info.buffer = buffer.get();
  info.format = VK_FORMAT_R32G32B32A32_UINT;
  info.range = VK_WHOLE_SIZE;
  VkBufferView view = VK_NULL_HANDLE;
  VK_CHECK(vkCreateBufferView(context.device(), &info, nullptr, &view));
  context.setName(VK_OBJECT_TYPE_BUFFER_VIEW, reinterpret_cast<uint64_t>(view), name);
  return gpu::BufferView(context.device(), view);
}

}  // namespace

GpuScene::GpuScene(const gpu::Context& context, const Scene& scene, const Bvh& bvh) {
  if (scene.textures.size() > gpu::kMaxTextureLayers)
    throw SceneError("scene '" + scene.name + "' has " + std::to_string(scene.textures.size()) +
                     " textures; at most " + std::to_string(gpu::kMaxTextureLayers) +
                     " are supported");
  vertices_ = uploadTexels(context, packVertices(scene), "scene vertices");
  triangles_ = uploadTexels(context, packTriangles(scene), "scene triangles");
  materials_ = uploadTexels(context, packMaterials(scene), "scene materials");
  std::vector<glm::vec3> corners;
  corners.reserve(scene.indices.size());
  for (uint32_t index : scene.indices) corners.push_back(scene.vertices[index].position);
  corners_ = gpu::createBufferWithData(context, std::span<const glm::vec3>(corners),
                                       VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, "triangle corners");
  lights_ = uploadTexels(context, scene.lights, "scene lights");
  PackedBvh packed = packBvh(bvh);
  if (packed.nodes.size() > gpu::kBvhMaxNodes)
    throw SceneError("scene '" + scene.name + "' is too large: its BVH has " +
                     std::to_string(packed.nodes.size()) + " nodes, at most " +
                     std::to_string(gpu::kBvhMaxNodes) + " are supported");
  bvhNodes_ = uploadTexels(context, packed.nodes, "bvh nodes");
  bvhTriangles_ = uploadTexels(context, packed.triangles, "bvh triangles");
  for (const gpu::Buffer* buffer :
       {&vertices_, &triangles_, &materials_, &lights_, &bvhNodes_, &bvhTriangles_})
    texelViews_.push_back(createTexelView(context, *buffer, "texels"));

  textures_ = uploadTextureArray(context, scene.textures);

  VkSamplerCreateInfo samplerInfo{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  samplerInfo.magFilter = VK_FILTER_LINEAR;
  samplerInfo.minFilter = VK_FILTER_LINEAR;
  samplerInfo.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
  samplerInfo.addressModeU = samplerInfo.addressModeV = samplerInfo.addressModeW =
      VK_SAMPLER_ADDRESS_MODE_REPEAT;
  samplerInfo.maxLod = VK_LOD_CLAMP_NONE;
  VkSampler sampler = VK_NULL_HANDLE;
  VK_CHECK(vkCreateSampler(context.device(), &samplerInfo, nullptr, &sampler));
  sampler_ = gpu::Sampler(context.device(), sampler);

  constexpr VkDescriptorType kTexels = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  constexpr VkDescriptorType kSampled = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  static_assert(gpu::kBindingVertices == 0 && gpu::kBindingTriangles == 1 &&
                gpu::kBindingMaterials == 2 && gpu::kBindingLights == 3 &&
                gpu::kBindingBvhNodes == 4 && gpu::kBindingBvhTriangles == 5 &&
                gpu::kBindingTextures == 6);
  std::vector<VkDescriptorSetLayoutBinding> bindings;
  for (VkDescriptorType type : {kTexels, kTexels, kTexels, kTexels, kTexels, kTexels, kSampled})
    bindings.push_back({uint32_t(bindings.size()), type, 1, gpu::kAllShaderStages, nullptr});
  setLayout_ = gpu::createSetLayout(context, std::move(bindings), false, "scene set");
  VkDescriptorPoolSize sizes[] = {{kTexels, 6}, {kSampled, 1}};
  VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  poolInfo.maxSets = 1;
  poolInfo.poolSizeCount = 2;
  poolInfo.pPoolSizes = sizes;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VK_CHECK(vkCreateDescriptorPool(context.device(), &poolInfo, nullptr, &pool));
  pool_ = gpu::DescriptorPool(context.device(), pool);
  VkDescriptorSetAllocateInfo allocInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  allocInfo.descriptorPool = pool_;
  allocInfo.descriptorSetCount = 1;
  VkDescriptorSetLayout layout = setLayout_.handle;
  allocInfo.pSetLayouts = &layout;
  VK_CHECK(vkAllocateDescriptorSets(context.device(), &allocInfo, &descriptorSet_));

  VkDescriptorImageInfo imageInfo{sampler_, textures_.view(),
                                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  std::vector<VkBufferView> views;
  for (const gpu::BufferView& view : texelViews_) views.push_back(view);
  auto write = [&](uint32_t binding, VkDescriptorType type) {
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = descriptorSet_;
    w.dstBinding = binding;
    w.descriptorCount = 1;
    w.descriptorType = type;
    return w;
  };
  std::vector<VkWriteDescriptorSet> writes;
  const uint32_t texelBindings[] = {gpu::kBindingVertices,  gpu::kBindingTriangles,
                                    gpu::kBindingMaterials, gpu::kBindingLights,
                                    gpu::kBindingBvhNodes,  gpu::kBindingBvhTriangles};
  for (size_t i = 0; i < views.size(); ++i) {
    writes.push_back(write(texelBindings[i], kTexels));
    writes.back().pTexelBufferView = &views[i];
  }
  writes.push_back(write(gpu::kBindingTextures, kSampled));
  writes.back().pImageInfo = &imageInfo;
  vkUpdateDescriptorSets(context.device(), static_cast<uint32_t>(writes.size()), writes.data(), 0,
                         nullptr);
}

void GpuScene::bind(VkCommandBuffer cmd, VkPipelineBindPoint bindPoint,
                    VkPipelineLayout layout) const {
  vkCmdBindDescriptorSets(cmd, bindPoint, layout, gpu::kSceneSet, 1, &descriptorSet_, 0, nullptr);
}

}  // namespace hdof
