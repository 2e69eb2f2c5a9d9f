// The planner's clearance hierarchy (oriented boxes, hints, piece order) against brute force: every
// answer must be the exact distance of the triangles, whatever the pruning did.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "clearance_bvh.hpp"

namespace tf {
namespace {
using Eigen::Vector3d;

// A wavy sheet (curved like a blade face, tessellated at `edge`), a sphere cap, and some random soup.
std::vector<Triangle> test_triangles(double edge, std::mt19937& rng) {
  std::vector<Triangle> t;
  auto sheet = [](double u, double v) {
    return Vector3d(u, v, 2.0 * std::sin(0.15 * u) + 0.05 * v * v / 10 + 0.3 * std::cos(0.4 * v));
  };
  const int n = static_cast<int>(std::ceil(30.0 / edge));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double u0 = -15 + 30.0 * i / n, u1 = -15 + 30.0 * (i + 1) / n;
      const double v0 = -15 + 30.0 * j / n, v1 = -15 + 30.0 * (j + 1) / n;
      t.push_back({sheet(u0, v0), sheet(u1, v0), sheet(u1, v1)});
      t.push_back({sheet(u0, v0), sheet(u1, v1), sheet(u0, v1)});
    }
  // A closed thin plate standing on the sheet (both faces close together, as a blade's).
  for (int j = 0; j < 20; ++j)
    for (int side = 0; side < 2; ++side) {
      const double x = side ? 4.0 : 3.2, z0 = -2 + 0.5 * j, z1 = z0 + 0.5;
      t.push_back({{x, -10, z0}, {x, 10, z0}, {x, 10, z1}});
      t.push_back({{x, -10, z0}, {x, 10, z1}, {x, -10, z1}});
    }
  std::uniform_real_distribution<double> U(-15, 15), small(-0.8, 0.8);
  for (int k = 0; k < 300; ++k) {
    const Vector3d c(U(rng), U(rng), U(rng) * 0.5 + 6);
    t.push_back({c, c + Vector3d(small(rng), small(rng), small(rng)), c + Vector3d(small(rng), small(rng), small(rng))});
  }
  // Degenerate ones: a sliver and a point.
  t.push_back({{1, 1, 8}, {2, 2, 8}, {3, 3, 8}});
  t.push_back({{-5, 4, 9}, {-5, 4, 9}, {-5, 4, 9}});
  return t;
}

double brute_point(const std::vector<Triangle>& tris, const Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : tris) best = std::min(best, (closest_point_on_triangle(p, t) - p).norm());
  return best;
}

double brute_cylinder(const std::vector<Triangle>& tris, const Vector3d& p0, const Vector3d& p1, double r) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : tris) best = std::min(best, triangle_cylinder_distance(t, p0, p1, r));
  return best;
}

TEST(ClearanceBvh, ClosestPointIsExact) {
  std::mt19937 rng(7);
  const auto tris = test_triangles(0.7, rng);
  const ClearanceBvh bvh(tris);
  ASSERT_EQ(bvh.size(), tris.size());
  std::uniform_real_distribution<double> U(-18, 18);
  int hint = -1;
  for (int k = 0; k < 300; ++k) {
    const Vector3d p(U(rng), U(rng), U(rng) * 0.4 + 3);
    const double want = brute_point(tris, p);
    const ClosestHit h = bvh.closest(p, std::numeric_limits<double>::infinity(), hint);
    ASSERT_GE(h.triangle, 0);
    EXPECT_NEAR(h.distance, want, 1e-12) << k;
    EXPECT_NEAR((h.point - p).norm(), want, 1e-12);
    hint = h.triangle;
    // Within a limit: a hit just above the distance, none just below it.
    EXPECT_NEAR(bvh.closest(p, want + 1e-3).distance, want, 1e-12);
    EXPECT_EQ(bvh.closest(p, want * 0.999).triangle, -1);
  }
}

TEST(ClearanceBvh, PieceDistancesAreExactWithAndWithoutHints) {
  std::mt19937 rng(11);
  const auto tris = test_triangles(0.6, rng);
  const ClearanceBvh bvh(tris);
  const TriangleBvh plain(tris);
  std::uniform_real_distribution<double> U(-12, 12), ang(-0.6, 0.6), rad(0.5, 4.0), len(2, 40);
  std::vector<int> hints(4, -1);
  Vector3d c(0, 0, 6), axis = Vector3d::UnitZ();
  for (int k = 0; k < 200; ++k) {
    // Half of the poses follow a walk (as consecutive rows do, hints then matter), half jump.
    if (k % 2) {
      c += Vector3d(0.3, 0.1, 0.02);
      axis = (axis + Vector3d(0.01, -0.02, 0)).normalized();
    } else {
      c = Vector3d(U(rng), U(rng), 3 + std::abs(U(rng)) * 0.5);
      axis = Vector3d(std::sin(ang(rng)), std::sin(ang(rng)), 1).normalized();
    }
    const Pose pose{c, axis};
    const double r = rad(rng), h0 = k % 3 == 0 ? 0.0 : len(rng) * 0.2, h1 = h0 + len(rng);
    const BodyPiece cyl{ToolComponent::Shank, -1, false, h0, h1, r};
    const BodyPiece ball{ToolComponent::Ball, -1, true, 0.0, 0.0, r};
    const double want_c = brute_cylinder(tris, c + h0 * axis, c + h1 * axis, r);
    const double want_b = std::max(0.0, brute_point(tris, c) - r);
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_NEAR(piece_distance(bvh, cyl, pose, inf), want_c, 2e-6) << k;
    EXPECT_NEAR(piece_distance(bvh, cyl, pose, inf, false, &hints[1]), want_c, 2e-6) << k;
    EXPECT_NEAR(piece_distance(plain, cyl, pose, inf), want_c, 2e-6) << k;
    EXPECT_NEAR(piece_distance(bvh, ball, pose, inf, false, &hints[0]), want_b, 1e-12) << k;
    // A limit: the exact value below it, a value >= limit above it; first_below answers the yes/no.
    for (const double limit : {0.5 * want_c, want_c + 0.01, 2 * want_c + 0.1}) {
      const double d = piece_distance(bvh, cyl, pose, limit, false, &hints[2]);
      const double yes = piece_distance(bvh, cyl, pose, limit, true, &hints[3]);
      if (want_c < limit - 2e-6) {
        EXPECT_NEAR(d, want_c, 2e-6);
        EXPECT_LT(yes, limit);
      } else if (want_c > limit + 2e-6) {
        EXPECT_GE(d, limit);
        EXPECT_GE(yes, limit);
      }
    }
  }
}

TEST(ClearanceBvh, WideCapOverTheSheetIsExact) {
  // A holder's face (radius 10-30) over the wavy sheet, tilted either way and facing it with either end:
  // the leaves decided by the cap's plane (a vertex standing over the disc) against GJK on every triangle.
  std::mt19937 rng(5);
  const auto tris = test_triangles(0.6, rng);
  const ClearanceBvh bvh(tris);
  std::uniform_real_distribution<double> U(-10, 10), ang(-0.5, 0.5), rad(10, 30), gap(0.05, 3);
  for (int k = 0; k < 40; ++k) {
    const Vector3d tilt = Vector3d(std::sin(ang(rng)), std::sin(ang(rng)), 1).normalized();
    const Vector3d c(U(rng), U(rng), 4.5 + gap(rng));
    // Even poses: the cylinder above c (its end at c faces the sheet); odd: the axis reversed, the far end
    // of the piece at c.
    const Vector3d axis = k % 2 ? Vector3d(-tilt) : tilt;
    const double len = 20;
    const double h0 = k % 2 ? -len : 0.0, h1 = h0 + len;
    const double r = rad(rng);
    const BodyPiece holder{ToolComponent::Holder, 0, false, h0, h1, r};
    const double want = brute_cylinder(tris, c + h0 * axis, c + h1 * axis, r);
    EXPECT_NEAR(piece_distance(bvh, holder, {c, axis}, std::numeric_limits<double>::infinity()), want, 2e-6) << k;
  }
}

TEST(ClearanceBvh, BodyClearanceMatchesThePlainHierarchy) {
  std::mt19937 rng(3);
  const auto tris = test_triangles(0.4, rng);
  const ClearanceBvh bvh(tris);
  const TriangleBvh plain(tris);
  // A ball-end tool body: ball, flutes, shank, two holder segments.
  const std::vector<BodyPiece> pieces = {{ToolComponent::Ball, -1, true, 0, 0, 3},
                                         {ToolComponent::Flute, -1, false, 0, 9, 3},
                                         {ToolComponent::Shank, -1, false, 9, 30, 3},
                                         {ToolComponent::Holder, 0, false, 30, 45, 8},
                                         {ToolComponent::Holder, 1, false, 45, 60, 12}};
  // Per part clearances: the shank its own (nothing joins), or the flutes' (flutes and shank join).
  for (const std::vector<double>& required : {std::vector<double>{1.0, 1.0, 1.5, 2.0, 2.0},
                                              std::vector<double>{1.0, 1.0, 1.0, 2.0, 2.0}}) {
    std::vector<BodyPiece> merged = pieces;
    std::vector<double> merged_required = required;
    merge_coaxial_pieces(merged, merged_required);
    ASSERT_EQ(merged.size(), required[2] == required[1] ? pieces.size() - 1 : pieces.size());
    if (merged.size() < pieces.size()) {
      EXPECT_EQ(merged[1].h0, 0);
      EXPECT_EQ(merged[1].h1, 30);
    }
    std::vector<int> hints, merged_hints;
    std::uniform_real_distribution<double> U(-10, 10), ang(-0.8, 0.8);
    for (int k = 0; k < 150; ++k) {
      const Vector3d c(U(rng), U(rng), 4.5 + 0.2 * U(rng));
      const Vector3d axis = Vector3d(std::sin(ang(rng)), std::sin(ang(rng)), 1).normalized();
      const BodyClearance want = body_clearance(plain, pieces, required, {c, axis});
      const BodyClearance a = body_clearance(bvh, pieces, required, {c, axis}, &hints);
      const BodyClearance m = body_clearance(bvh, merged, merged_required, {c, axis}, &merged_hints);
      EXPECT_NEAR(a.distance, want.distance, 2e-6) << k;
      EXPECT_NEAR(a.margin, want.margin, 2e-6) << k;
      EXPECT_NEAR(m.distance, want.distance, 2e-6) << k;
      EXPECT_NEAR(m.margin, want.margin, 2e-6) << k;
    }
  }
}

}  // namespace
}  // namespace tf
