// Shared set-up for GPU tests: one Vulkan context per test binary, scenes loaded once, and a
// helper that renders an image of a scene in a mode.
#pragma once

#include "gpu/context.h"
#include "image/image.h"
#include "render/frame_pipeline.h"
#include "scene/bvh.h"
#include "scene/gpu_scene.h"

#include <map>
#include <memory>
#include <optional>
#include <string>

namespace hdof::test {

inline const std::string kLivingRoom = HDOF_ASSETS_DIR "/scenes/living-room/living-room.gltf";

struct SceneOnGpu {
  Scene scene;
  Bvh bvh;
  std::unique_ptr<GpuScene> gpu;
};

gpu::Context& testContext();
SceneOnGpu& testScene(const std::string& spec);

struct RenderSpec {
  std::string scene = "builtin:dof";
  std::string camera;  // empty: the first
  RenderMode mode = RenderMode::Pinhole;
  uint32_t width = 160, height = 90;
  uint32_t raysPerPixel = 1;  // reference: in total; raytrace: per frame
  uint32_t frames = 1;        // raytrace: frames of a still camera
  bool pixelJitter = true;
  bool traceEverywhere = false;  // hybrid: a full ray mask
  Lens lens{50.0f, 2.8f, 0.0f};  // focus distance 0: the camera's suggestion, else 5 m
  float znear = 0.0f;            // the near clipping plane, metres; 0: the scene camera's
  // The scene camera moved to look from eye at target (y up), when given.
  std::optional<glm::vec3> eye, target;
};

// The lens on the sensor on which its focal length frames an image of this size as the scene
// camera does (a sensor of the image's aspect, 2 f tan(fov / 2) on each side): the scene camera's
// framing with the lens's blur, which these tests' expectations are worked out for.
Lens onSceneCameraSensor(Lens lens, const SceneCamera& camera, uint32_t width, uint32_t height);

// The frame request of the spec's first frame, its lens on the scene camera's sensor.
FrameRequest requestFor(const RenderSpec& spec, const Scene& scene);
ImageRgba8 renderImage(const RenderSpec& spec);
// The spec's view in `mode`, with `rays` per pixel (reference: in all; else each frame) over
// `frames` frames of a still camera.
ImageRgba8 renderImage(RenderSpec spec, RenderMode mode, uint32_t rays = 1, uint32_t frames = 1);
// A pipeline for the spec's view that has rendered its first frame (spec.mode, spec.raysPerPixel
// rays per pixel), for tests that read its images back.
std::unique_ptr<FramePipeline> renderFirstFrame(const RenderSpec& spec);
// The pinhole frame's linear depth, with the request the spec makes (for CoC parameters).
std::vector<float> renderDepth(RenderSpec spec, FrameRequest* request = nullptr);

// Frames of a truck to the right, `step` metres a frame, whose last frame is the request's view.
void renderTruckOnto(FramePipeline& pipeline, FrameRequest request, int frames, float step);

// The partial-occlusion region of the spec's view (255 inside), from its pinhole depth.
std::vector<uint8_t> occlusionRegion(const RenderSpec& spec);

// A render target's texels on the CPU (rgba16f, rg16f, r16f, rgba32f or r8ui images; the
// channels an image lacks are 0).
std::vector<glm::vec4> readImage(const gpu::Image& image);

// Mean squared error over RGB, in 8-bit units squared.
double meanSquaredError(const ImageRgba8& a, const ImageRgba8& b);

}  // namespace hdof::test
