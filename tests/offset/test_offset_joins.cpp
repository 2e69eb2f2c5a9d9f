// The join cases (Gawlik, Karbowski, Ruszaj, section 3.1) with hand-computed results.
#include "offset_test_util.hpp"

namespace tf::offset::test {
namespace {
using Eigen::Vector2d;

bool has_vertex(const OffsetResult& r, const Vector2d& p, double tol = 1e-9) {
  for (const auto& c : r.contours)
    for (const auto& s : c)
      if ((s.a - p).norm() <= tol) return true;
  return false;
}

// 1.A line-line: the offset lines of a square meet at their intersections.
TEST(OffsetJoins, LineLineJoinIsTheIntersectionOfTheOffsetLines) {
  const Profile p = profile_text("START 0 0\n0 20 0\n0 0 20\n0 -20 0\n0 0 -20\n");
  for (Corner corner : {Corner::Round, Corner::Sharp}) {
    OffsetOptions o;
    o.corner = corner;
    const auto r = offset_profile(p, constant_gap(2.0), o);
    ASSERT_EQ(r.contours.size(), 1u);
    ASSERT_EQ(r.contours[0].size(), 4u);
    for (const Vector2d& v : {Vector2d(2, 2), Vector2d(18, 2), Vector2d(18, 18), Vector2d(2, 18)})
      EXPECT_TRUE(has_vertex(r, v)) << v.transpose();
    EXPECT_NEAR(total_area(r), 16.0 * 16.0, 1e-9);
  }
  // Outside with sharp corners: the same construction on the far side.
  OffsetOptions o;
  o.side = Side::Outside;
  o.corner = Corner::Sharp;
  const auto r = offset_profile(p, constant_gap(2.0), o);
  ASSERT_EQ(r.contours.size(), 1u);
  for (const Vector2d& v : {Vector2d(-2, -2), Vector2d(22, -2), Vector2d(22, 22), Vector2d(-2, 22)})
    EXPECT_TRUE(has_vertex(r, v)) << v.transpose();
  EXPECT_NEAR(total_area(r), 24.0 * 24.0, 1e-9);
  // Round: arcs of radius D about the corners, area 20^2 + 4*20*2 + pi*2^2.
  o.corner = Corner::Round;
  EXPECT_NEAR(total_area(offset_profile(p, constant_gap(2.0), o)), 400 + 160 + M_PI * 4, 1e-9);
}

// Sharp corners beside a gap law: the neighbours' offsets are not parallel to their elements, and the join
// at the corner where the law varies had been kept round (black-box testing). Every corner is mitred,
// never closer than the law.
TEST(OffsetJoins, SharpCornersBesideAGapLaw) {
  const Profile p = profile_text("START 0 0\n0 40 0\n0 0 30\n0 -40 0\n0 0 -30\n");
  const GapLaw law{{0, 20, 40, 60, 140}, {1, 1, 1.2, 1, 1}, 0.0, ""};
  OffsetOptions o;
  o.side = Side::Outside;
  o.corner = Corner::Sharp;
  const auto r = offset_profile(p, law, o);
  ASSERT_EQ(r.contours.size(), 1u);
  for (const Segment& s : r.contours[0]) EXPECT_NE(s.kind, SegmentKind::RoundJoin) << s.a.transpose();
  const auto e = check_exactness(p, law, r, 128);
  EXPECT_GE(e.min_sharp, -1e-9);
  EXPECT_GE(e.min_transition, -1e-6);
}

// 1.B line-arc, R > 0, trajectory inside: the arc's offset has R' = R - D about the same centre and
// meets the offset line at their intersection.
TEST(OffsetJoins, LineArcPositiveRadiusInside) {
  const Profile p = profile_text("START 0 0\n0 20 0\n15 0 20\n0 -20 0\n0 0 -20\n");
  const Vector2d centre(20 - std::sqrt(15.0 * 15 - 10 * 10), 10);
  const auto r = offset_profile(p, constant_gap(2.0), {});
  ASSERT_EQ(r.contours.size(), 1u);
  int arcs = 0;
  for (const auto& s : r.contours[0])
    if (s.is_arc()) {
      ++arcs;
      EXPECT_NEAR(s.r, 13.0, 1e-12);
      EXPECT_LE((s.c - centre).norm(), 1e-12);
      EXPECT_GT(s.sweep, 0);
    }
  EXPECT_EQ(arcs, 1);
  EXPECT_TRUE(has_vertex(r, Vector2d(centre.x() + std::sqrt(13.0 * 13 - 8 * 8), 2)));
  EXPECT_TRUE(has_vertex(r, Vector2d(centre.x() + std::sqrt(13.0 * 13 - 8 * 8), 18)));
}

// 2.A line-arc, R < 0, trajectory outside: R' = R + D (the notch's radius shrinks by D).
TEST(OffsetJoins, LineArcNegativeRadiusOutside) {
  const Profile p = profile_text("START 0 0\n0 40 0\n0 0 20\n0 -10 0\n-10 -20 0\n0 -10 0\n0 0 -20\n");
  OffsetOptions o;
  o.side = Side::Outside;
  const auto r = offset_profile(p, constant_gap(2.0), o);
  ASSERT_EQ(r.contours.size(), 1u);
  int notch = 0;
  for (const auto& s : r.contours[0])
    if (s.is_arc() && s.kind == SegmentKind::Element) {
      ++notch;
      EXPECT_NEAR(s.r, 8.0, 1e-12);
      EXPECT_LE((s.c - Vector2d(20, 20)).norm(), 1e-12);
      EXPECT_LT(s.sweep, 0);
    }
  EXPECT_EQ(notch, 1);
  // The notch's corners are convex seen from outside: round joins of radius D about them ...
  int corner_arcs = 0;
  for (const auto& s : r.contours[0])
    if (s.kind == SegmentKind::RoundJoin && std::abs(s.r - 2.0) < 1e-12 &&
        ((s.c - Vector2d(30, 20)).norm() < 1e-12 || (s.c - Vector2d(10, 20)).norm() < 1e-12))
      ++corner_arcs;
  EXPECT_EQ(corner_arcs, 2);
  // ... and with sharp corners the paper's construction: the offset line y = 22 meets the circle R' = 8.
  o.corner = Corner::Sharp;
  const auto sharp = offset_profile(p, constant_gap(2.0), o);
  EXPECT_TRUE(has_vertex(sharp, Vector2d(20 + std::sqrt(60.0), 22)));
  EXPECT_TRUE(has_vertex(sharp, Vector2d(20 - std::sqrt(60.0), 22)));
  // Inside the same notch grows: R' = |R| + D about the same centre.
  const auto in = offset_profile(p, constant_gap(2.0), {});
  bool grown = false;
  for (const auto& s : in.contours.at(0))
    if (s.is_arc() && std::abs(s.r - 12.0) < 1e-12 && (s.c - Vector2d(20, 20)).norm() < 1e-12) grown = true;
  EXPECT_TRUE(grown);
}

// An arc whose radius is below the gap vanishes from the inside offset.
TEST(OffsetJoins, VanishingArcIsRemoved) {
  const Profile p = profile_text("START 0 0\n0 20 0\n0 0 10\n1 0 2\n0 0 10\n0 -20 0\n0 0 -22\n");
  // The small bump (R = 1 on the right edge) is convex: inside D = 2 > R makes it vanish.
  const auto r = offset_profile(p, constant_gap(2.0), {});
  ASSERT_EQ(r.contours.size(), 1u);
  for (const auto& s : r.contours[0]) EXPECT_FALSE(s.is_arc() && s.r < 1.5);
  EXPECT_LE(check_exactness(p, constant_gap(2.0), r).max_error, 1e-9);
}

}  // namespace
}  // namespace tf::offset::test
