// Frustum culling keeps what the camera can see and drops what is behind or beside it.
#include "render/camera.h"
#include "render/raster_culling.h"

#include <gtest/gtest.h>

namespace hdof {
namespace {

void addCorners(Scene& scene, std::initializer_list<glm::vec3> corners) {
  for (glm::vec3 corner : corners) {
    gpu::Vertex v{};
    v.position = corner;
    scene.indices.push_back(static_cast<uint32_t>(scene.vertices.size()));
    scene.vertices.push_back(v);
  }
}

void addTriangle(Scene& scene, glm::vec3 center, float size = 0.1f) {
  addCorners(scene, {center + glm::vec3(-size, 0, 0), center + glm::vec3(size, 0, 0),
                     center + glm::vec3(0, size, 0)});
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

// A run across a plane of the frustum (its triangles may need clipping) is drawn on its own.
TEST(RasterCulling, DrawsRunsAcrossTheFrustumAlone) {
  Scene scene;
  addTriangle(scene, {0, 0, -5});
  addTriangle(scene, {0, 0, -5}, 50.0f);  // across the sides
  addTriangle(scene, {0.5f, 0, -6});
  addTriangle(scene, {0, 0.2f, -3});
  addCorners(scene, {{0, 0, -2}, {0, 0, 2}, {1, 0, 0}});  // across the near plane
  addCorners(scene, {{0, 0, -2}, {0, 0, 2}, {-1, 0, 0}});
  std::vector<TriangleRun> runs = buildTriangleRuns(scene, 1);
  Camera camera;
  FrameSettings settings;
  gpu::FrameUniforms u = makeFrameUniforms(scene, camera, Lens{}, settings);
  std::vector<TriangleRange> ranges = visibleTriangles(runs, u.viewProj);
  std::vector<std::pair<uint32_t, uint32_t>> got;
  for (const TriangleRange& range : ranges)
    got.emplace_back(range.firstTriangle, range.triangleCount);
  std::vector<std::pair<uint32_t, uint32_t>> expected{{0, 1}, {1, 1}, {2, 2}, {4, 1}, {5, 1}};
  EXPECT_EQ(got, expected);
}

}  // namespace
}  // namespace hdof
