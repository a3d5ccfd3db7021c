// Frustum culling keeps what the camera can see and drops what is behind or beside it.
#include "render/camera.h"
#include "render/raster_culling.h"

#include <gtest/gtest.h>

namespace hdof {
namespace {

void addTriangle(Scene& scene, glm::vec3 center) {
  for (glm::vec3 offset : {glm::vec3(-0.1f, 0, 0), glm::vec3(0.1f, 0, 0), glm::vec3(0, 0.1f, 0)}) {
    gpu::Vertex v{};
    v.position = center + offset;
    scene.indices.push_back(static_cast<uint32_t>(scene.vertices.size()));
    scene.vertices.push_back(v);
  }
}

TEST(RasterCulling, KeepsVisibleRunsAndMergesNeighbours) {
  Scene scene;
  addTriangle(scene, {0, 0, -5});     // in front
  addTriangle(scene, {0.5f, 0, -6});  // in front
  addTriangle(scene, {0, 0, 5});      // behind
  addTriangle(scene, {100, 0, -5});   // far to the right
  addTriangle(scene, {0, 0.2f, -3});  // in front
  std::vector<TriangleRun> runs = buildTriangleRuns(scene, 1);
  ASSERT_EQ(runs.size(), 5u);
  Camera camera;  // at the origin looking down -z
  FrameSettings settings;
  gpu::FrameUniforms u = makeFrameUniforms(scene, camera, Lens{}, settings);
  std::vector<TriangleRange> ranges = visibleTriangles(runs, u.viewProj);
  ASSERT_EQ(ranges.size(), 2u);
  EXPECT_EQ(ranges[0].firstTriangle, 0u);
  EXPECT_EQ(ranges[0].triangleCount, 2u);
  EXPECT_EQ(ranges[1].firstTriangle, 4u);
  EXPECT_EQ(ranges[1].triangleCount, 1u);
}

}  // namespace
}  // namespace hdof
