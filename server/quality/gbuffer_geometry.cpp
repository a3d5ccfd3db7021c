#include "quality/gbuffer_geometry.h"

#include "gpu/resources.h"

#include <glm/vec4.hpp>

namespace hdof {

GBufferGeometry readGBufferGeometry(const gpu::Context& context, const FramePipeline& pipeline) {
  const gpu::Image& image = pipeline.images().gbuffer.normalDepth;  // rgba32f
  size_t texels = size_t(image.width()) * image.height();
  gpu::Buffer buffer(context, texels * sizeof(glm::vec4), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                     gpu::MemoryUse::Readback, "normal depth readback");
  context.submitAndWait([&](VkCommandBuffer cmd) { gpu::copyImageToBuffer(cmd, image, buffer); });
  const auto* data = static_cast<const glm::vec4*>(buffer.mapped());
  GBufferGeometry geometry;
  geometry.linearDepth.resize(texels);
  geometry.normals.resize(texels);
  for (size_t i = 0; i < texels; ++i) {
    geometry.normals[i] = glm::vec3(data[i]);
    geometry.linearDepth[i] = data[i].w;
  }
  return geometry;
}

}  // namespace hdof
