#include "scene/bvh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace hdof {
namespace {

const std::string kLivingRoom =
    std::string(HDOF_ASSETS_DIR) + "/scenes/living-room/living-room.gltf";

const Scene& livingRoom() {
  static const Scene scene = loadScene(kLivingRoom);
  return scene;
}

// Random rays from inside and around the bounds in random directions, some with a finite range;
// the BVH must find the same closest hit as testing every triangle.
void expectSameHitsAsBruteForce(const Scene& scene, const Bvh& bvh, int rayCount, uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::normal_distribution<float> gaussian;
  glm::vec3 margin = 0.2f * scene.bounds.extent();
  glm::vec3 low = scene.bounds.min - margin, span = scene.bounds.extent() + 2.0f * margin;
  int hits = 0, differentTriangles = 0;
  for (int ray = 0; ray < rayCount; ++ray) {
    glm::vec3 origin = low + span * glm::vec3(unit(random), unit(random), unit(random));
    glm::vec3 direction(gaussian(random), gaussian(random), gaussian(random));
    if (ray % 3 == 0) direction *= 7.5f;  // direction need not be unit length
    float tMin = ray % 4 == 0 ? 0.1f * unit(random) : 0.0f;
    float tMax = ray % 5 == 0 ? 2.0f * unit(random) : std::numeric_limits<float>::infinity();
    std::optional<RayHit> expected =
        intersectBruteForce(scene.vertices, scene.indices, origin, direction, tMin, tMax);
    std::optional<RayHit> actual = intersect(bvh, origin, direction, tMin, tMax);
    ASSERT_EQ(expected.has_value(), actual.has_value()) << "ray " << ray;
    if (!expected) continue;
    ++hits;
    ASSERT_NEAR(actual->t, expected->t, 1e-4f * expected->t) << "ray " << ray;
    EXPECT_GT(actual->t, tMin);
    EXPECT_LT(actual->t, tMax);
    if (actual->triangle != expected->triangle) {
      // Only a tie (a ray through a shared edge or coincident faces) may pick another triangle.
      ASSERT_EQ(actual->t, expected->t) << "ray " << ray;
      ++differentTriangles;
    } else {
      EXPECT_EQ(actual->u, expected->u);
      EXPECT_EQ(actual->v, expected->v);
    }
  }
  EXPECT_GT(hits, rayCount / 10) << "too few rays hit anything to test much";
  EXPECT_LT(differentTriangles, rayCount / 100 + 1);
}

// Depth, leaf coverage and bounds: every triangle in exactly one leaf, children adjacent and
// inside their parent, every leaf's triangles inside its box.
void expectWellFormed(const Scene& scene, const Bvh& bvh) {
  ASSERT_FALSE(bvh.nodes.empty());
  ASSERT_EQ(bvh.triangles.size(), scene.triangleCount());
  EXPECT_LT(bvh.depth, gpu::kBvhStackSize);
  std::vector<int> seen(scene.triangleCount(), 0);
  std::vector<size_t> leafCoverage(bvh.triangles.size(), 0);
  uint32_t maxDepth = 0;
  struct Visit {
    uint32_t node, depth;
  };
  std::vector<Visit> stack{{0, 1}};
  auto inside = [](const glm::vec3& p, const gpu::BvhNode& node) {
    return glm::all(glm::greaterThanEqual(p, node.boundsMin)) &&
           glm::all(glm::lessThanEqual(p, node.boundsMax));
  };
  while (!stack.empty()) {
    Visit visit = stack.back();
    stack.pop_back();
    maxDepth = std::max(maxDepth, visit.depth);
    const gpu::BvhNode& node = bvh.nodes.at(visit.node);
    if (node.triangleCount > 0) {
      ASSERT_LE(size_t{node.leftOrFirst} + node.triangleCount, bvh.triangles.size());
      for (uint32_t i = node.leftOrFirst; i < node.leftOrFirst + node.triangleCount; ++i) {
        ++leafCoverage[i];
        const gpu::BvhTriangle& triangle = bvh.triangles[i];
        ASSERT_LT(triangle.index, scene.triangleCount());
        ++seen[triangle.index];
        for (int corner = 0; corner < 3; ++corner) {
          uint32_t vertex = scene.indices[3 * triangle.index + corner];
          EXPECT_TRUE(inside(scene.vertices[vertex].position, node));
        }
      }
      continue;
    }
    ASSERT_LT(node.leftOrFirst + 1, bvh.nodes.size());
    ASSERT_GT(node.leftOrFirst, visit.node) << "children come after their parent";
    for (uint32_t child = node.leftOrFirst; child <= node.leftOrFirst + 1; ++child) {
      EXPECT_TRUE(inside(bvh.nodes[child].boundsMin, node));
      EXPECT_TRUE(inside(bvh.nodes[child].boundsMax, node));
      stack.push_back({child, visit.depth + 1});
    }
  }
  EXPECT_EQ(maxDepth, bvh.depth);
  for (size_t t = 0; t < seen.size(); ++t) ASSERT_EQ(seen[t], 1) << "triangle " << t;
  for (size_t i = 0; i < leafCoverage.size(); ++i) ASSERT_EQ(leafCoverage[i], 1u) << "slot " << i;
  // A binary tree whose interior nodes all have two children.
  size_t leaves = 0;
  for (const gpu::BvhNode& node : bvh.nodes) leaves += node.triangleCount > 0;
  EXPECT_EQ(bvh.nodes.size(), 2 * leaves - 1);
}

// Triangle i sits at x = 2^-i with size 0.1 * 2^-i: split in the middle of the centroids (two
// bins), every split peels off the largest one, so without a depth limit the tree would be as
// deep as the triangle count.
Scene geometricStaircase(int triangleCount) {
  Scene scene;
  scene.materials.push_back(
      gpu::Material{glm::vec4(1.0f), glm::vec3(0.0f), 0.0f, 1.0f, gpu::kNoTexture});
  for (int i = 0; i < triangleCount; ++i) {
    float x = std::ldexp(1.0f, -i), size = 0.1f * x;
    uint32_t first = static_cast<uint32_t>(scene.vertices.size());
    for (glm::vec3 corner :
         {glm::vec3(x, 0, 0), glm::vec3(x + size, 0, 0), glm::vec3(x, size, 0)}) {
      scene.vertices.push_back(gpu::Vertex{corner, 0.0f, glm::vec3(0, 0, 1), 0, glm::vec2(0.0f)});
    }
    scene.indices.insert(scene.indices.end(), {first, first + 1, first + 2});
  }
  finalizeScene(scene);
  return scene;
}

TEST(Bvh, NoLeafHoldsMoreTrianglesThanTheGpuNodesCount) {
  // Copies of one triangle: no split separates them, yet the leaves keep within the limit.
  std::vector<gpu::Vertex> vertices(3);
  vertices[1].position = {1, 0, 0};
  vertices[2].position = {0, 1, 0};
  std::vector<uint32_t> indices;
  for (uint32_t copy = 0; copy < 3 * gpu::kBvhMaxLeafTriangles; ++copy)
    indices.insert(indices.end(), {0, 1, 2});
  Bvh bvh = buildBvh(vertices, indices);
  size_t leafTriangles = 0;
  for (const gpu::BvhNode& node : bvh.nodes) {
    EXPECT_LE(node.triangleCount, gpu::kBvhMaxLeafTriangles);
    leafTriangles += node.triangleCount;
  }
  EXPECT_EQ(leafTriangles, indices.size() / 3);
  EXPECT_GT(bvh.nodes.size(), 1u);
}

TEST(Bvh, BuiltinSceneMatchesBruteForce) {
  Scene scene = makeBuiltinScene("dof");
  Bvh bvh = buildBvh(scene.vertices, scene.indices);
  expectWellFormed(scene, bvh);
  expectSameHitsAsBruteForce(scene, bvh, 4000, 1);
}

TEST(Bvh, LivingRoomMatchesBruteForce) {
  const Scene& scene = livingRoom();
  Bvh bvh = buildBvh(scene.vertices, scene.indices);
  expectWellFormed(scene, bvh);
  EXPECT_GT(bvh.buildMs, 0.0);
  expectSameHitsAsBruteForce(scene, bvh, 2000, 2);
}

TEST(Bvh, OtherBuildOptionsStayCorrect) {
  Scene scene = makeBuiltinScene("dof");
  for (BvhBuildOptions options : {BvhBuildOptions{4, 1}, BvhBuildOptions{32, 16}}) {
    Bvh bvh = buildBvh(scene.vertices, scene.indices, options);
    expectWellFormed(scene, bvh);
    expectSameHitsAsBruteForce(scene, bvh, 1000, 3);
  }
}

TEST(Bvh, DepthStaysBelowTheTraversalStack) {
  const int triangleCount = 120;
  Scene scene = geometricStaircase(triangleCount);
  Bvh bvh = buildBvh(scene.vertices, scene.indices, {2, 1});
  expectWellFormed(scene, bvh);
  EXPECT_GT(bvh.depth, 40u) << "the input should have made a deep tree";
  // Smaller triangles fall below the intersection test's determinant threshold.
  for (int i = 0; i < 15; ++i) {
    float x = std::ldexp(1.0f, -i), quarter = 0.025f * x;
    std::optional<RayHit> hit = intersect(bvh, {x + quarter, quarter, 1.0f}, {0, 0, -1});
    ASSERT_TRUE(hit.has_value()) << i;
    EXPECT_EQ(hit->triangle, static_cast<uint32_t>(i));
  }
}

TEST(Bvh, SingleTriangleHitHasExpectedDistanceAndBarycentrics) {
  std::vector<gpu::Vertex> vertices(3);
  vertices[0].position = {0, 0, 0};
  vertices[1].position = {1, 0, 0};
  vertices[2].position = {0, 1, 0};
  std::vector<uint32_t> indices{0, 1, 2};
  Bvh bvh = buildBvh(vertices, indices);
  ASSERT_EQ(bvh.nodes.size(), 1u);
  EXPECT_EQ(bvh.depth, 1u);

  std::optional<RayHit> hit = intersect(bvh, {0.25f, 0.5f, 2.0f}, {0, 0, -1});
  ASSERT_TRUE(hit.has_value());
  EXPECT_FLOAT_EQ(hit->t, 2.0f);
  EXPECT_FLOAT_EQ(hit->u, 0.25f);
  EXPECT_FLOAT_EQ(hit->v, 0.5f);
  EXPECT_EQ(hit->triangle, 0u);
  // Both faces count: no culling.
  EXPECT_TRUE(intersect(bvh, {0.25f, 0.25f, -1.0f}, {0, 0, 1}).has_value());
  // The range is exclusive at both ends and respected.
  EXPECT_FALSE(intersect(bvh, {0.25f, 0.5f, 2.0f}, {0, 0, -1}, 0.0f, 1.5f).has_value());
  EXPECT_FALSE(intersect(bvh, {0.25f, 0.5f, 2.0f}, {0, 0, -1}, 2.5f).has_value());
  EXPECT_FALSE(intersect(bvh, {0.25f, 0.5f, 2.0f}, {0, 0, 1}).has_value());
  EXPECT_FALSE(intersect(bvh, {0.75f, 0.75f, 2.0f}, {0, 0, -1}).has_value());
  // A ray parallel to the triangle's plane.
  EXPECT_FALSE(intersect(bvh, {-1.0f, 0.25f, 0.0f}, {1, 0, 0}).has_value());
}

TEST(Bvh, RaysThroughASharedEdgeDoNotSlipThrough) {
  // A unit quad as two triangles sharing the diagonal from (0,0) to (1,1).
  std::vector<gpu::Vertex> vertices(4);
  vertices[0].position = {0, 0, 0};
  vertices[1].position = {1, 0, 0};
  vertices[2].position = {1, 1, 0};
  vertices[3].position = {0, 1, 0};
  std::vector<uint32_t> indices{0, 1, 2, 0, 2, 3};
  Bvh bvh = buildBvh(vertices, indices, {16, 1});
  for (int i = 1; i < 64; ++i) {
    float s = static_cast<float>(i) / 64.0f;
    glm::vec3 origin(s, s, 1.0f);
    EXPECT_TRUE(intersect(bvh, origin, {0, 0, -1}).has_value()) << s;
    EXPECT_TRUE(intersect(bvh, origin + glm::vec3(0.3f, -0.1f, 0), {-0.3f, 0.1f, -1}).has_value());
  }
}

TEST(Bvh, EmptyInputGivesARootThatNothingHits) {
  Bvh bvh = buildBvh({}, {});
  ASSERT_EQ(bvh.nodes.size(), 1u);
  EXPECT_TRUE(bvh.triangles.empty());
  EXPECT_FALSE(intersect(bvh, {0, 0, 0}, {0, 0, 1}).has_value());
}

}  // namespace
}  // namespace hdof
