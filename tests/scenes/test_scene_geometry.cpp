// The generators' geometry helpers and the SVG renderer.
#include <gtest/gtest.h>

#include <set>

#include "scenes/render_svg.hpp"
#include "scenes/scene_distance.hpp"
#include "scenes/scene_geometry.hpp"
#include "scene_test_util.hpp"

using namespace scene_test;
namespace sc = tf::scenes;

namespace {

TEST(SceneGeometry, SampleByChordKeepsAnArcWithinTheTolerance) {
  const double r = 25.0, tol = 0.003;
  auto arc = [&](double t) { return std::vector<Eigen::Vector3d>{{r * std::cos(t), r * std::sin(t), 0.0}}; };
  const std::vector<double> t = sc::sample_by_chord(arc, 0.0, 2.0, tol);
  ASSERT_GT(t.size(), 10u);
  EXPECT_DOUBLE_EQ(t.front(), 0.0);
  EXPECT_DOUBLE_EQ(t.back(), 2.0);
  double worst = 0;
  for (size_t i = 1; i < t.size(); ++i) {
    ASSERT_GT(t[i], t[i - 1]);
    const double half = 0.5 * (t[i] - t[i - 1]);
    worst = std::max(worst, r * (1 - std::cos(half)));  // sagitta of the chord
  }
  EXPECT_LE(worst, tol);
  EXPECT_GT(worst, tol / 8);  // not absurdly fine either
}

TEST(SceneGeometry, RevolvedCylinderIsClosedOutwardWithTheRightVolume) {
  const int n = sc::circle_segments(10.0, 0.01);
  EXPECT_LE(10.0 * (1 - std::cos(M_PI / n)), 0.01);
  const tf::Mesh m = sc::revolve_profile({{0, 0}, {10, 0}, {10, 5}, {0, 5}}, n);
  EXPECT_TRUE(tf::is_closed(m));
  EXPECT_TRUE(consistently_oriented(to_soup(m)));
  const double polygon_area = 0.5 * n * 100.0 * std::sin(2 * M_PI / n);
  EXPECT_NEAR(tf::signed_volume(m), polygon_area * 5.0, 1e-6);
}

TEST(SceneGeometry, PrismAndBoxAreClosedOutward) {
  const tf::Mesh p = sc::extrude_along_x({{0, 0}, {4, 0}, {3, 2}, {1, 2}}, -1, 2);
  EXPECT_TRUE(tf::is_closed(p));
  EXPECT_NEAR(tf::signed_volume(p), 6.0 * 3.0, 1e-12);  // trapezoid area 6, length 3
  const tf::Mesh b = sc::box_mesh({1, 2, 3}, {2, 4, 7});
  EXPECT_NEAR(tf::signed_volume(b), 8.0, 1e-12);
  EXPECT_TRUE(consistently_oriented(to_soup(b)));
}

TEST(SceneGeometry, ResamplePolylineSpacesPointsByAtMostTheStep) {
  const auto pts = sc::resample_polyline({{0, 0, 0}, {10, 0, 0}, {10, 3, 0}}, 0.7);
  ASSERT_FALSE(pts.empty());
  EXPECT_TRUE(pts.front().isZero());
  EXPECT_TRUE(pts.back().isApprox(Eigen::Vector3d(10, 3, 0)));
  for (size_t i = 1; i < pts.size(); ++i) {
    EXPECT_LE((pts[i] - pts[i - 1]).norm(), 0.7 + 1e-12);
    EXPECT_GT((pts[i] - pts[i - 1]).norm(), 0.5);
  }
}

TEST(SceneGeometry, ToolAxisHitsSeesAWallOverTheToolButNotBeside) {
  const tf::Tool tool = sc::ball_tool(3.0);
  const tf::Mesh shelf = sc::box_mesh({-50, 5, 20}, {50, 30, 25});  // a shelf 20 mm up, from y = 5
  const tf::TriangleBvh wall({&shelf});
  EXPECT_TRUE(sc::tool_axis_hits(tool, wall, {0, 6, 3}, Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(sc::tool_axis_hits(tool, wall, {0, 3, 3}, Eigen::Vector3d::UnitZ()));   // shank radius reaches y = 6
  EXPECT_FALSE(sc::tool_axis_hits(tool, wall, {0, 1.5, 3}, Eigen::Vector3d::UnitZ()));  // 0.5 mm beside
  EXPECT_FALSE(sc::tool_axis_hits(tool, wall, {0, 6, 3}, Eigen::Vector3d(0, -1, 0)));
}

TEST(RenderSvg, DrawsVisibleFacesAndThePathAndStaysSmall) {
  const tf::Mesh box = sc::box_mesh({0, 0, 0}, {10, 10, 10});
  sc::SvgOptions o;
  o.title = "a <box>";
  const std::string svg = sc::render_svg({{&box, {0.5, 0.5, 0.5}}}, {{{{0, 0, 12}, {10, 10, 12}}}}, o);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  // An oblique view of a box shows three faces (their triangles maybe split), each flat-shaded.
  std::set<std::string> fills;
  for (size_t at = svg.find("fill=\"#"); at != std::string::npos; at = svg.find("fill=\"#", at + 1))
    fills.insert(svg.substr(at + 6, 7));
  fills.erase("#ffffff");  // the background
  fills.erase("#333333");  // the title
  EXPECT_EQ(fills.size(), 3u);
  EXPECT_NE(svg.find("<polyline"), std::string::npos);
  EXPECT_NE(svg.find("a &lt;box&gt;"), std::string::npos);

  // A large mesh is decimated to the budget.
  const tf::Mesh fine = sc::revolve_profile({{0, 0}, {30, 0}, {30, 10}, {0, 10}}, 4000);
  ASSERT_GT(fine.n_faces(), 15000u);
  o.max_triangles = 3000;
  const std::string small = sc::render_svg({{&fine, {0.5, 0.5, 0.5}}}, {}, o);
  size_t n = 0;
  for (size_t at = small.find("<polygon"); at != std::string::npos; at = small.find("<polygon", at + 1)) ++n;
  EXPECT_GT(n, 100u);
  EXPECT_LE(n, 3000u + 1500u);
}

}  // namespace
