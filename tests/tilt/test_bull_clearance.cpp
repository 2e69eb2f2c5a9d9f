// A bull end's clearance is its torus', not its enclosing cylinder's: against the closed form of the
// distance from a point to the rounded disc, and against FCL's distance to a finely tessellated copy of
// the end (an independent GJK on an inscribed polytope).
#include <gtest/gtest.h>

#include <fcl/fcl.h>

#include <cmath>
#include <numbers>
#include <random>

#include "bull_end_fcl.hpp"
#include "clearance_bvh.hpp"

namespace tf {
namespace {
using Eigen::Vector3d;

Tool bull_tool(double R, double r) {
  Tool t;
  t.cutter = BullCutter{R, r};
  t.flute_length = 15;
  t.shank_radius = R;
  t.length = 40;
  return t;
}

// Distance from p to the bull end of tool frame (cutter location c, unit axis a): the disc of radius R - r
// about c normal to a, rounded by r. Written from the shape, not from the code under test.
double closed_form(const Vector3d& p, const Vector3d& c, const Vector3d& a, double R, double r) {
  const Vector3d q = p - c;
  const double along = q.dot(a), radial = (q - along * a).norm();
  const double to_disc = radial <= R - r ? std::abs(along) : std::hypot(along, radial - (R - r));
  return std::max(0.0, to_disc - r);
}

TEST(BullClearance, TheEndIsItsRoundedDisc) {
  const Tool tool = bull_tool(3.0, 1.0);
  const std::vector<BodyPiece> pieces = body_pieces(tool);
  ASSERT_FALSE(pieces.empty());
  const BodyPiece& end = pieces.front();
  EXPECT_EQ(end.component, ToolComponent::Ball);
  EXPECT_DOUBLE_EQ(end.rounding, 1.0);
  EXPECT_DOUBLE_EQ(end.h0, -1.0);
  EXPECT_DOUBLE_EQ(end.h1, 1.0);
  // Flutes shorter than twice the corner radius: the rounded disc would reach above them, the enclosing
  // cylinder stays.
  Tool short_flutes = tool;
  short_flutes.flute_length = 1.5;
  EXPECT_DOUBLE_EQ(body_pieces(short_flutes).front().rounding, 0.0);
}

TEST(BullClearance, PointsMatchTheClosedForm) {
  const double R = 3.0, r = 1.0;
  const BodyPiece end = body_pieces(bull_tool(R, r)).front();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-5, 5), ang(-0.8, 0.8);
  const double inf = std::numeric_limits<double>::infinity();
  int corner_points = 0;
  for (int k = 0; k < 400; ++k) {
    const Vector3d c(U(rng), U(rng), U(rng));
    const Vector3d a = Vector3d(std::sin(ang(rng)), std::sin(ang(rng)), 1).normalized();
    const Vector3d p = c + Vector3d(U(rng), U(rng), U(rng)) * 0.9;
    const std::vector<Triangle> tris{{p, p, p}};
    const ClearanceBvh bvh(tris);
    const TriangleBvh plain(tris);
    const double want = closed_form(p, c, a, R, r);
    int hint = -1;
    EXPECT_NEAR(piece_distance(bvh, end, Pose{c, a}, inf, false, &hint), want, 2e-6) << k;
    EXPECT_NEAR(piece_distance(plain, end, Pose{c, a}, inf), want, 2e-6) << k;
    // Where the corner matters: beside and below the rim, the cylinder would be nearer.
    const Vector3d q = p - c;
    const double along = q.dot(a), radial = (q - along * a).norm();
    corner_points += radial > R - r && along < 0 && want > 0;
  }
  EXPECT_GT(corner_points, 40);
}

TEST(BullClearance, TrianglesMatchFclOnATessellatedEnd) {
  const double R = 4.0, r = 1.5;
  const BodyPiece end = body_pieces(bull_tool(R, r)).front();
  // 720 around and 180 over the tube: the polytope lies within R (1 - cos(0.25 deg)) < 4e-5 mm inside.
  const auto fcl_end = test::bull_end_convex(R, r, 720, 180);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> U(-6, 6), small(-2, 2), ang(-0.7, 0.7);
  const double inf = std::numeric_limits<double>::infinity();
  int checked = 0;
  for (int k = 0; k < 150; ++k) {
    const Vector3d c(0, 0, 0);
    const Vector3d a = Vector3d(std::sin(ang(rng)), std::sin(ang(rng)), 1).normalized();
    const Vector3d t0(U(rng), U(rng), U(rng));
    const Triangle t{t0, t0 + Vector3d(small(rng), small(rng), small(rng)),
                     t0 + Vector3d(small(rng), small(rng), small(rng))};
    const std::vector<Triangle> tris{t};
    const ClearanceBvh bvh(tris);
    const double ours = piece_distance(bvh, end, Pose{c, a}, inf);

    auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
    model->beginModel();
    model->addTriangle(t.a, t.b, t.c);
    model->endModel();
    fcl::Transform3d pose = fcl::Transform3d::Identity();
    pose.linear() = Eigen::Quaterniond::FromTwoVectors(Vector3d::UnitZ(), a).toRotationMatrix();
    pose.translation() = c;
    fcl::CollisionObjectd mesh(model, fcl::Transform3d::Identity()), body(fcl_end, pose);
    fcl::DistanceRequestd req;
    req.gjk_solver_type = fcl::GST_INDEP;
    fcl::DistanceResultd res;
    fcl::distance(&mesh, &body, req, res);
    if (res.min_distance <= 0) {
      EXPECT_LT(ours, 1e-4) << k << ": FCL finds contact";
      continue;
    }
    // The polytope is inside the end: FCL's distance is at least ours, by at most the tessellation's depth.
    EXPECT_NEAR(ours, res.min_distance, 1e-4) << k;
    ++checked;
  }
  EXPECT_GT(checked, 60);
}

}  // namespace
}  // namespace tf
