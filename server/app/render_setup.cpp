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
  parser.option("--focal-length", "MM", "lens focal length in millimetres (default 50)",
                &options.focalLengthMm);
  parser.option("--f-number", "N",
                "aperture f-number, at least 0.5 (default 2.8; 1e6 is a pinhole)",
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

Lens resolveLens(const LensOptions& options, const LoadedScene& loaded, const std::string& camera) {
  if (!(options.fNumber >= 0.5f))
    throw UsageError("--f-number must be at least 0.5 (got " + std::to_string(options.fNumber) +
                     ")");
  if (!(options.focalLengthMm > 0.0f && options.focalLengthMm <= 5000.0f))
    throw UsageError("--focal-length must be more than 0 and at most 5000 mm");
  if (options.focusDistance < 0.0f || options.focusDistance > 1e5f)
    throw UsageError("--focus-distance must be more than 0 and at most 100000 m");
  if (options.blades == 1 || options.blades == 2 || options.blades > 16)
    throw UsageError("--blades must be 0 (circle) or 3 to 16");
  Lens lens;
  lens.focalLengthMm = options.focalLengthMm;
  lens.fNumber = options.fNumber;
  lens.blades = options.blades;
  lens.focusDistance = options.focusDistance;
  if (lens.focusDistance == 0.0f) {
    const SceneCamera* sceneCamera =
        camera.empty() ? &loaded.scene.cameras.front() : loaded.scene.findCamera(camera);
    if (sceneCamera && sceneCamera->focusDistance) {
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
              resolveLens(lensOptions, loaded, sceneOptions.camera),
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
