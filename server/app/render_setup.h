// What the rendering subcommands share: options for the scene, camera, lens and device, how they
// turn into a loaded scene, a camera and a lens (with user-facing errors), and the set-up that
// renders frames of that view.
#pragma once

#include "app/cli.h"
#include "gpu/context.h"
#include "render/camera_path.h"
#include "render/frame_pipeline.h"
#include "scene/bvh.h"
#include "scene/gpu_scene.h"
#include "scene/scene.h"

#include <string>

namespace hdof {

struct SceneOptions {
  std::string scene = "builtin:dof";
  std::string camera;  // empty: the scene's first camera
  std::string device;
  bool verbose = false;
};

struct LensOptions {
  float focalLengthMm = 0.0f;  // 0: the one that keeps the scene camera's field of view
  std::string sensor = "full-frame";
  float fNumber = 2.8f;
  float focusDistance = 0.0f;  // 0: the camera's suggestion, else autofocus at the image centre
  uint32_t blades = 0;
};

void addSceneOptions(ArgParser& parser, SceneOptions& options);
void addLensOptions(ArgParser& parser, LensOptions& options);

struct LoadedScene {
  Scene scene;
  Bvh bvh;
  double loadMs = 0.0;
};

LoadedScene loadSceneWithBvh(const SceneOptions& options);
// The named camera (or the first); throws UsageError listing the scene's cameras.
Camera resolveCamera(const Scene& scene, const std::string& name);
// The lens from the options for an image of this size; focal length from the options or the
// scene camera's field of view on the sensor; focus distance from the options, the scene camera's
// suggestion, or the distance to the surface at the centre of the image. Throws UsageError on
// bad values.
Lens resolveLens(const LensOptions& options, const LoadedScene& loaded, const std::string& camera,
                 Size2 size);
// "WxH" in millimetres or a preset's name; throws UsageError naming the choices.
Sensor parseSensor(const std::string& text);
// The lens a report was made with, as one line of key=value pairs (focal length, f-number,
// focus, sensor and the field of view they give at this size).
std::string lensSummary(const Lens& lens, Size2 size);
gpu::ContextOptions contextOptions(const SceneOptions& options);

// The scene on a device with a frame pipeline of the given size, and a request for the view
// the options describe (camera, lens, size; mode pinhole).
struct RenderSetup {
  RenderSetup(const SceneOptions& sceneOptions, const LensOptions& lensOptions, Size2 size);
  LoadedScene loaded;
  FrameRequest request;
  gpu::Context context;
  GpuScene gpuScene;
  FramePipeline pipeline;
};

// The camera path in a file; throws UsageError with the file's problem.
CameraPath loadCameraPath(const std::string& file);

double median(std::vector<double> values);

}  // namespace hdof
