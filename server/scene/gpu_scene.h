// A scene and its BVH on the GPU: the buffers and textures of descriptor set 0, uploaded once and
// shared by every pass and every session.
#pragma once

#include "gpu/program.h"
#include "scene/bvh.h"
#include "scene/scene.h"

namespace hdof {

class GpuScene {
 public:
  GpuScene(const gpu::Context& context, const Scene& scene, const Bvh& bvh);

  // Set 0 of every program that reads the scene (shaders/lib/scene.glsl declares it).
  const gpu::SetLayout& setLayout() const { return setLayout_; }
  VkDescriptorSet descriptorSet() const { return descriptorSet_; }
  // Binds descriptor set 0 for a pipeline whose layout starts with setLayout().
  void bind(VkCommandBuffer cmd, VkPipelineBindPoint bindPoint, VkPipelineLayout layout) const;
  // Every triangle's corner positions in order (three vec3 per triangle), for the raster.
  const gpu::Buffer& cornerBuffer() const { return corners_; }

 private:
  gpu::Buffer vertices_, triangles_, materials_, lights_, bvhNodes_, bvhTriangles_;  // texel rows
  std::vector<gpu::BufferView> texelViews_;  // of the six above, in that order
  gpu::Buffer corners_;
  gpu::Image textures_;  // a 2D array, one layer per scene texture
  gpu::Sampler sampler_;
  gpu::SetLayout setLayout_;
  gpu::DescriptorPool pool_;
  VkDescriptorSet descriptorSet_ = VK_NULL_HANDLE;
};

}  // namespace hdof
