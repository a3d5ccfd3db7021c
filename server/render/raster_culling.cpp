#include "render/raster_culling.h"

#include <algorithm>

namespace hdof {
namespace {

enum class FrustumSide { Outside, Inside, Crossing };

// Where a box lies against the view frustum: wholly outside one of its planes, wholly inside all
// of them, or across some.
FrustumSide frustumSide(const Aabb& box, const glm::mat4& viewProj) {
  // Per clip plane, whether all eight corners are outside it, and whether any is.
  bool allOutside[6] = {true, true, true, true, true, true};
  bool anyOutside = false;
  for (int corner = 0; corner < 8; ++corner) {
    glm::vec3 p((corner & 1) ? box.max.x : box.min.x, (corner & 2) ? box.max.y : box.min.y,
                (corner & 4) ? box.max.z : box.min.z);
    glm::vec4 c = viewProj * glm::vec4(p, 1.0f);
    bool outside[6] = {c.x<-c.w, c.x> c.w, c.y<-c.w, c.y> c.w, c.z<0.0f, c.z> c.w};
    for (int plane = 0; plane < 6; ++plane) {
      allOutside[plane] &= outside[plane];
      anyOutside |= outside[plane];
    }
  }
  if (std::any_of(std::begin(allOutside), std::end(allOutside), [](bool b) { return b; }))
    return FrustumSide::Outside;
  return anyOutside ? FrustumSide::Crossing : FrustumSide::Inside;
}

}  // namespace

std::vector<TriangleRun> buildTriangleRuns(const Scene& scene, uint32_t trianglesPerRun) {
  std::vector<TriangleRun> runs;
  uint32_t triangles = static_cast<uint32_t>(scene.triangleCount());
  for (uint32_t first = 0; first < triangles; first += trianglesPerRun) {
    TriangleRun run;
    run.firstTriangle = first;
    run.triangleCount = std::min(trianglesPerRun, triangles - first);
    for (uint32_t i = first * 3; i < (first + run.triangleCount) * 3; ++i)
      run.bounds.grow(scene.vertices[scene.indices[i]].position);
    runs.push_back(run);
  }
  return runs;
}

std::vector<TriangleRange> visibleTriangles(const std::vector<TriangleRun>& runs,
                                            const glm::mat4& viewProj) {
  std::vector<TriangleRange> ranges;
  bool mergeNext = false;  // whether the last range is of inside runs and ends at this run
  for (const TriangleRun& run : runs) {
    FrustumSide side = frustumSide(run.bounds, viewProj);
    if (side == FrustumSide::Outside) {
      mergeNext = false;
      continue;
    }
    bool inside = side == FrustumSide::Inside;
    if (mergeNext && inside)
      ranges.back().triangleCount += run.triangleCount;
    else
      ranges.push_back({run.firstTriangle, run.triangleCount});
    mergeNext = inside;
  }
  return ranges;
}

}  // namespace hdof
