// The G-buffer, in three steps: a raster visibility pass (shaders/gbuffer.vert, .frag) writes the
// triangle seen at each pixel's sample position, a compute resolve (gbuffer_resolve.comp) shades
// that point once per pixel with the shading code the ray tracer uses, into colour, specular,
// normal/depth and motion, and the anti-aliasing (antialias.comp) accumulates the colour over
// frames: jittered samples while the view rests, reprojected history while it moves. A still
// view's later frames raster kStillRasterSamples samples per pixel (multisampled), and the resolve
// shades each triangle among them once.
#pragma once

#include "render/frame_images.h"
#include "render/raster_culling.h"
#include "render/steps.h"

#include <shared/frame.h>

#include <memory>

namespace hdof {

class GBufferPass {
 public:
  GBufferPass(const gpu::Context& context, const Scene& scene, const GpuScene& gpuScene);

  // Makes the framebuffers for a new set of images (call after they change).
  void bindImages(const GBufferImages& images, uint32_t width, uint32_t height);
  // The steps "visibility", "gbuffer" (the resolve) and "antialias". uniforms: the frame's (its
  // viewProj culls on the CPU; its rasterSample picks the anti-aliasing's pipeline).
  // historyValid: images.color holds the previous frame's anti-aliased colour (false after a cut
  // or on a new viewport).
  void record(StepRecorder& steps, const GBufferImages& images, const gpu::FrameUniforms& uniforms,
              bool historyValid) const;

 private:
  // The visibility pass's pipeline layout, and its render passes and pipelines at one sample per
  // pixel and at kStillRasterSamples: made once, shared by every session (Context::shared).
  struct Rasters;

  void drawVisibility(VkCommandBuffer cmd, bool multisampled, const gpu::Bind& frame,
                      const gpu::FrameUniforms& uniforms) const;

  const gpu::Context& context_;
  const GpuScene& scene_;
  std::vector<TriangleRun> runs_;
  std::shared_ptr<const Rasters> rasters_;
  gpu::Framebuffer singleFramebuffer_, multisampledFramebuffer_;
  VkExtent2D extent_{};
  // gbuffer_resolve.comp for one sample per pixel; for a multisampled frame, its steps for the
  // first triangle of each pixel's samples and for the others, and the dispatch size of the last
  // (ray_mask_indirect.comp).
  gpu::ComputeProgram resolve_, resolveFirstTriangle_, resolveOtherTriangles_, sharedIndirect_;
  // antialias.comp for a still view's later samples, for the frames in motion, and for the first
  // frame after a cut.
  gpu::ComputeProgram antialiasStill_, antialias_, antialiasFirst_;
};

}  // namespace hdof
