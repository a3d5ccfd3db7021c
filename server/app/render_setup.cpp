#include "app/render_setup.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace hdof {

void addSceneOptions(ArgParser& parser, SceneOptions& options) {
  parser.option("--scene", "PATH|builtin:NAME",
                "scene to render: a .gltf/.glb file or a built-in (default builtin:dof)",
                &options.scene);
  parser.option("--camera", "NAME", "the scene's camera to look through (default: its first)",
                &options.camera);
  parser.option("--device", "INDEX|NAME",
                "Vulkan device by index or name substring (default: a GPU, else lavapipe)",
                &options.device);
  parser.flag("--verbose", "print the devices, the chosen one and timings to stderr",
              &options.verbose);
}

void addLensOptions(ArgParser& parser, LensOptions& options) {
  parser.option("--focal-length", "MM",
                "lens focal length in millimetres; with the sensor it sets the field of view "
                "(default: the one that keeps the scene camera's field of view)",
                &options.focalLengthMm);
  parser.option("--sensor", "WxH|NAME",
                "sensor size in millimetres, or " + sensorPresetNames() +
                    " (default full-frame, 36x24); the image is the largest rectangle of its "
                    "aspect on the sensor",
                &options.sensor);
  // The command's own default (hdof quality measures wide open).
  char defaultFNumber[32];
  std::snprintf(defaultFNumber, sizeof defaultFNumber, "%g", double(options.fNumber));
  parser.option("--f-number", "N",
                std::string("aperture f-number, at least 0.5 (default ") + defaultFNumber +
                    "; 1e6 is a pinhole)",
                &options.fNumber);
  parser.option("--focus-distance", "M",
                "focus distance in metres (default: the camera's, else the surface at the centre)",
                &options.focusDistance);
  parser.option("--blades", "N", "aperture blades, 0 for a circular aperture (default 0)",
                &options.blades);
}

LoadedScene loadSceneWithBvh(const SceneOptions& options) {
  auto start = std::chrono::steady_clock::now();
  LoadedScene loaded{loadScene(options.scene), {}};
  loaded.bvh = buildBvh(loaded.scene.vertices, loaded.scene.indices);
  loaded.loadMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (options.verbose)
    std::fprintf(stderr, "scene %s: %zu triangles, BVH %zu nodes depth %u in %.1f ms\n",
                 loaded.scene.name.c_str(), loaded.scene.triangleCount(), loaded.bvh.nodes.size(),
                 loaded.bvh.depth, loaded.bvh.buildMs);
  return loaded;
}

Camera resolveCamera(const Scene& scene, const std::string& name) {
  if (name.empty()) return Camera::fromScene(scene.cameras.front());
  if (const SceneCamera* camera = scene.findCamera(name)) return Camera::fromScene(*camera);
  std::string names;
  for (const SceneCamera& c : scene.cameras) names += (names.empty() ? "" : ", ") + c.name;
  throw UsageError("scene '" + scene.name + "' has no camera named '" + name +
                   "' (its cameras: " + names + ")");
}

Sensor parseSensor(const std::string& text) {
  if (auto preset = sensorPreset(text)) return *preset;
  std::string problem = "--sensor must be WxH in millimetres (e.g. 36x24), each side " +
                        std::to_string(int(kMinSensorMm)) + " to " +
                        std::to_string(int(kMaxSensorMm)) + ", or one of " + sensorPresetNames() +
                        " (got '" + text + "')";
  size_t x = text.find('x');
  if (x == std::string::npos) throw UsageError(problem);
  Sensor sensor;
  try {
    sensor.widthMm = float(parseNumber(text.substr(0, x), "--sensor"));
    sensor.heightMm = float(parseNumber(text.substr(x + 1), "--sensor"));
  } catch (const UsageError&) {
    throw UsageError(problem);
  }
  for (float side : {sensor.widthMm, sensor.heightMm})
    if (!(side >= kMinSensorMm && side <= kMaxSensorMm)) throw UsageError(problem);
  return sensor;
}

std::string lensSummary(const Lens& lens, Size2 size) {
  glm::vec2 fov = fieldOfViewDeg(lens, size.width, size.height);
  char text[200];
  std::snprintf(text, sizeof(text),
                "focal_length_mm=%.1f f_number=%.3g focus_distance=%.3f sensor_mm=%.4gx%.4g "
                "fov_deg=%.1fx%.1f",
                lens.focalLengthMm, lens.fNumber, lens.focusDistance, lens.sensor.widthMm,
                lens.sensor.heightMm, fov.x, fov.y);
  return text;
}

Lens resolveLens(const LensOptions& options, const LoadedScene& loaded, const std::string& camera,
                 Size2 size) {
  if (!(options.fNumber >= 0.5f))
    throw UsageError("--f-number must be at least 0.5 (got " + std::to_string(options.fNumber) +
                     ")");
  if (!(options.focalLengthMm >= 0.0f && options.focalLengthMm <= 5000.0f))
    throw UsageError("--focal-length must be more than 0 and at most 5000 mm");
  if (options.focusDistance < 0.0f || options.focusDistance > 1e5f)
    throw UsageError("--focus-distance must be more than 0 and at most 100000 m");
  if (options.blades == 1 || options.blades == 2 || options.blades > 16)
    throw UsageError("--blades must be 0 (circle) or 3 to 16");
  Lens lens;
  lens.sensor = parseSensor(options.sensor);
  lens.fNumber = options.fNumber;
  lens.blades = options.blades;
  lens.focusDistance = options.focusDistance;
  const SceneCamera* sceneCamera =
      camera.empty() ? &loaded.scene.cameras.front() : loaded.scene.findCamera(camera);
  if (!sceneCamera) resolveCamera(loaded.scene, camera);  // throws, naming the scene's cameras
  lens.focalLengthMm = options.focalLengthMm;
  if (lens.focalLengthMm == 0.0f)
    lens = withSceneCameraFov(lens, *sceneCamera, size.width, size.height);
  if (lens.focusDistance == 0.0f) {
    if (sceneCamera->focusDistance) {
      lens.focusDistance = *sceneCamera->focusDistance;
    } else {
      Camera c = resolveCamera(loaded.scene, camera);
      auto hit = intersect(loaded.bvh, c.position, c.forward);
      lens.focusDistance = hit ? std::max(hit->t, 0.05f) : 10.0f;
    }
  }
  return lens;
}

gpu::ContextOptions contextOptions(const SceneOptions& options) {
  gpu::ContextOptions context;
  context.device = options.device;
  context.verbose = options.verbose;
  return context;
}

RenderSetup::RenderSetup(const SceneOptions& sceneOptions, const LensOptions& lensOptions,
                         Size2 size)
    : loaded(loadSceneWithBvh(sceneOptions)),
      request{RenderMode::Pinhole,
              resolveCamera(loaded.scene, sceneOptions.camera),
              resolveLens(lensOptions, loaded, sceneOptions.camera, size),
              {size.width, size.height}},
      context(contextOptions(sceneOptions)),
      gpuScene(context, loaded.scene, loaded.bvh),
      pipeline(context, loaded.scene, gpuScene, size.width, size.height) {}

CameraPath loadCameraPath(const std::string& file) {
  try {
    return CameraPath::load(file);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace hdof
