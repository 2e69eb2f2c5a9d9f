// Exact triangle distances and the triangle hierarchy's nearest-point query against brute force.
#include <gtest/gtest.h>

#include <random>

#include "tiltfield/core/scene.hpp"
#include "tiltfield/core/triangle_bvh.hpp"

namespace tf {
namespace {

Mesh cylinder_mesh() {
  Stock s;
  s.kind = Stock::Kind::Cylinder;
  s.cylinder = {{1.0, -2.0, 0.0}, Eigen::Vector3d(0.2, 0.1, 1.0).normalized(), 10.0, 9.0};
  return stock_to_mesh(s, 40);
}

TEST(Triangle, ClosestPointSnapsToFaceEdgeOrCorner) {
  const Triangle t{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_TRUE(closest_point_on_triangle({0.2, 0.2, 3}, t).isApprox(Eigen::Vector3d(0.2, 0.2, 0)));
  EXPECT_TRUE(closest_point_on_triangle({-1, -1, 0}, t).isApprox(t.a));
  EXPECT_TRUE(closest_point_on_triangle({1, 1, 0}, t).isApprox(Eigen::Vector3d(0.5, 0.5, 0)));
  // A degenerate triangle is its longest edge.
  const Triangle line{{0, 0, 0}, {2, 0, 0}, {1, 0, 0}};
  EXPECT_TRUE(closest_point_on_triangle({1.5, 1, 0}, line).isApprox(Eigen::Vector3d(1.5, 0, 0)));
  // A segment through the triangle is at distance 0; one above it at its height.
  EXPECT_DOUBLE_EQ(segment_triangle_distance({0.2, 0.2, -1}, {0.2, 0.2, 1}, t), 0.0);
  EXPECT_NEAR(segment_triangle_distance({0.2, 0.2, 2}, {0.3, 0.1, 3}, t), 2.0, 1e-12);
}

TEST(TriangleBvh, NearestPointAgreesWithBruteForce) {
  const Mesh m = cylinder_mesh();
  const TriangleBvh bvh({&m});
  const std::vector<Triangle> tris = mesh_triangles({&m});
  ASSERT_EQ(bvh.size(), tris.size());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-16, 16);
  int hint = -1;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng) * 0.6 + 4);
    double brute = std::numeric_limits<double>::infinity();
    for (const Triangle& t : tris) brute = std::min(brute, (closest_point_on_triangle(p, t) - p).norm());
    const ClosestHit hit = bvh.closest(p, std::numeric_limits<double>::infinity(), hint);
    EXPECT_NEAR(hit.distance, brute, 1e-12) << i;
    EXPECT_NEAR((hit.point - p).norm(), brute, 1e-12) << i;
    ASSERT_GE(hit.triangle, 0);
    EXPECT_NEAR((closest_point_on_triangle(p, bvh.triangle(hit.triangle)) - p).norm(), brute, 1e-12);
    hint = hit.triangle;  // hints only speed the search up
    // Within a limit: the same point, or nothing when the limit is not above the distance.
    EXPECT_NEAR(bvh.closest(p, brute + 1e-9).distance, brute, 1e-12);
    EXPECT_TRUE(std::isinf(bvh.closest(p, brute * 0.999).distance));
  }
}

TEST(TriangleBvh, EmptyHierarchyFindsNothing) {
  const TriangleBvh bvh(std::vector<Triangle>{});
  EXPECT_TRUE(bvh.empty());
  EXPECT_EQ(bvh.closest({0, 0, 0}).triangle, -1);
  EXPECT_TRUE(std::isinf(bvh.closest({0, 0, 0}).distance));
}

}  // namespace
}  // namespace tf
