// Re-planning: windows around verified collisions, blended back smoothly; the stock as an obstacle for the
// non-cutting part of the tool; the collisions read back from a verification report.
#include <gtest/gtest.h>

#include <cmath>

#include "replan/hidden_post_scene.hpp"
#include "test_support.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/local_frame.hpp"
#include "tiltfield/core/report.hpp"
#include "tiltfield/replan/replan.hpp"

namespace {
using tf::test::write_hidden_post_scene;

TEST(Replan, RowsOutsideTheWindowsAreUnchangedAndEndsAreSmooth) {
  tf::test::TempDir dir;
  const tf::Scene scene = tf::load_scene(write_hidden_post_scene(dir));
  const tf::PlanOptions po =
      tf::parse_plan_options(scene.planner_json, scene.file.string(), scene.tool, scene.planner, scene.feed);
  const tf::PlanResult planned = tf::plan(scene, po);
  // A holder collision at x = 20, as the verifier would report it.
  tf::Collision site;
  site.component = tf::ToolComponent::Holder;
  site.with = tf::HitWith::Stock;
  site.start = {Eigen::Vector3d(19.5, 0, 0), Eigen::Vector3d::UnitZ()};
  site.end = {Eigen::Vector3d(20, 0, 0), Eigen::Vector3d::UnitZ()};
  const tf::Mesh obstacle = tf::stock_obstacle(tf::stock_to_mesh(scene.stock), scene.path, scene.tool, scene.planner, 1.5, 0.5);
  const tf::ReplanOptions ro;
  const tf::ReplanResult r = tf::replan(scene, planned.path, {site}, {&obstacle}, po, ro);
  ASSERT_EQ(r.windows.size(), 1u);
  const auto& w = r.windows[0];
  EXPECT_LE(w.first, 119u);
  EXPECT_GE(w.last, 120u);
  EXPECT_GT(w.first, 0u);
  EXPECT_LT(w.last, r.path.rows.size() - 1);
  EXPECT_GT(r.rows_changed, 0u);
  EXPECT_EQ(r.rows_below_safety, 0u);
  for (size_t i = 0; i < r.path.rows.size(); ++i) {
    if (i >= w.first && i <= w.last) continue;
    EXPECT_EQ(r.path.rows[i].axis, planned.path.rows[i].axis) << "row " << i;
  }
  // C1 at the window ends: with a smoothstep blend over n rows the first step is about 3/n^2 of the
  // change and the largest about 1.5/n, so the end steps stay below a fifth of the largest step; a C0
  // (linear) blend would make them two thirds of it.
  auto step = [&](size_t i) { return std::acos(std::clamp(r.path.rows[i].axis.dot(r.path.rows[i + 1].axis), -1.0, 1.0)); };
  double largest = 0;
  for (size_t i = w.first; i < w.last; ++i) largest = std::max(largest, step(i));
  ASSERT_GT(largest, 0.0);
  if (w.first > 0) {
    EXPECT_LT(step(w.first), 0.2 * largest + 1e-9);
  }
  if (w.last + 1 < r.path.rows.size()) {
    EXPECT_LT(step(w.last - 1), 0.2 * largest + 1e-9);
  }
}

// The hidden-post scene planned without knowing of a fixture box [lo, hi], which is then added to it (with
// a fixture clearance of 2 mm).
struct FixtureCase {
  tf::Scene scene;
  tf::PlanOptions options;
  tf::PlanResult planned;
  FixtureCase(const tf::test::TempDir& dir, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi)
      : scene(tf::load_scene(write_hidden_post_scene(dir))),
        options(tf::parse_plan_options(scene.planner_json, scene.file.string(), scene.tool, scene.planner, scene.feed)),
        planned(tf::plan(scene, options)) {
    scene.fixtures.push_back(tf::test::box(lo, hi));
    scene.planner.fixture_clearance = 2.0;
  }
};

// The post as a fixture the plan did not know: the holder collision is re-planned against the fixture,
// with the fixture clearance, and a collision of the ball itself is left alone with its reason.
TEST(Replan, FixtureCollisionIsReplannedAgainstTheFixture) {
  tf::test::TempDir dir;
  const FixtureCase fc(dir, {15, 8, 1}, {25, 20, 80});
  const tf::Scene& scene = fc.scene;
  const tf::PlanOptions& po = fc.options;
  const tf::PlanResult& planned = fc.planned;
  const tf::PlanObstacles only_fixture{{}, {&scene.fixtures[0]}, {}};
  std::vector<size_t> rows;
  for (size_t i = 100; i <= 140; ++i) rows.push_back(i);
  double before = 1e9;
  for (const auto& c : tf::row_clearances(planned.path, rows, scene.tool, scene.planner, only_fixture))
    before = std::min(before, c.margin_mm);
  EXPECT_LT(before, 0.0);  // the plan without the fixture meets it

  tf::Collision site;
  site.component = tf::ToolComponent::Holder;
  site.with = tf::HitWith::Fixture;
  site.start = {Eigen::Vector3d(19.5, 0, 0), Eigen::Vector3d::UnitZ()};
  site.end = {Eigen::Vector3d(20, 0, 0), Eigen::Vector3d::UnitZ()};
  tf::Collision ball = site;
  ball.component = tf::ToolComponent::Ball;
  EXPECT_TRUE(tf::unfixable_reason(site, scene.tool).empty());
  EXPECT_NE(tf::unfixable_reason(ball, scene.tool).find("ball itself"), std::string::npos);
  // A flat or bull end swings with the axis: its collision at a cutter location is re-planned (black-box
  // testing: a bull end's 322 collisions with a fixture had been passed over), its approach's is not.
  tf::Tool flat = scene.tool, bull = scene.tool;
  flat.cutter = tf::FlatCutter{scene.tool.radius()};
  bull.cutter = tf::BullCutter{scene.tool.radius(), 1.0};
  EXPECT_TRUE(tf::unfixable_reason(ball, flat).empty());
  EXPECT_TRUE(tf::unfixable_reason(ball, bull).empty());
  EXPECT_TRUE(tf::unfixable_reasons({ball, site}, {{119, 120}, {119, 120}}, bull)[1].empty());
  EXPECT_FALSE(tf::unfixable_reasons({ball, site}, {{119, 120}, {119, 120}}, scene.tool)[1].empty());
  tf::Collision approach = ball;  // down a tilted axis onto the row, as written to 4 decimals: an approach
  approach.start.axis = approach.end.axis = Eigen::Vector3d(0.5, 0, std::sqrt(0.75));
  approach.start.tip = Eigen::Vector3d(35.0001, 0, 25.9807);
  EXPECT_NE(tf::unfixable_reason(approach, scene.tool).find("along the tool axis (the post's approach or retract)"),
            std::string::npos)
      << tf::unfixable_reason(approach, scene.tool);
  EXPECT_FALSE(tf::unfixable_reason(approach, flat).empty());
  EXPECT_TRUE(tf::replan(scene, planned.path, {ball}, {}, po).windows.empty());

  const tf::ReplanResult r = tf::replan(scene, planned.path, {site}, {}, po);
  ASSERT_EQ(r.windows.size(), 1u);
  EXPECT_EQ(r.rows_below_safety, 0u);
  rows.clear();
  for (size_t i = r.windows[0].first; i <= r.windows[0].last; ++i) rows.push_back(i);
  for (const auto& c : tf::row_clearances(r.path, rows, scene.tool, scene.planner, only_fixture))
    EXPECT_GE(c.margin_mm, -0.01);  // at least fixture_clearance from the post
}

// A window that reaches the path's first row re-plans that row too: there is no axis before it to blend
// back to (row 0 had kept its old axis, below its clearance; black-box testing).
TEST(Replan, WindowAtThePathsStartReplansItsFirstRow) {
  tf::test::TempDir dir;
  const FixtureCase fc(dir, {-45, 8, 1}, {-35, 20, 80});
  const tf::Scene& scene = fc.scene;
  const tf::PlanOptions& po = fc.options;
  const tf::PlanResult& planned = fc.planned;
  const tf::PlanObstacles only_fixture{{}, {&scene.fixtures[0]}, {}};
  EXPECT_LT(tf::row_clearances(planned.path, {0}, scene.tool, scene.planner, only_fixture)[0].margin_mm, 0.0);
  tf::Collision site;
  site.component = tf::ToolComponent::Holder;
  site.with = tf::HitWith::Fixture;
  site.start = {Eigen::Vector3d(-40, 0, 0), Eigen::Vector3d::UnitZ()};
  site.end = {Eigen::Vector3d(-39.5, 0, 0), Eigen::Vector3d::UnitZ()};
  const tf::ReplanResult r = tf::replan(scene, planned.path, {site}, {}, po);
  ASSERT_EQ(r.windows.size(), 1u);
  EXPECT_EQ(r.windows[0].first, 0u);
  EXPECT_EQ(r.rows_below_safety, 0u);
  EXPECT_GE(tf::row_clearances(r.path, {0}, scene.tool, scene.planner, only_fixture)[0].margin_mm, -0.01);
}

TEST(Replan, StockObstacleKeepsOnlyWhatTheCuttingPartCannotReach) {
  tf::test::TempDir dir;
  const tf::Scene scene = tf::load_scene(write_hidden_post_scene(dir));
  const tf::Mesh obstacle = tf::stock_obstacle(tf::stock_to_mesh(scene.stock), scene.path, scene.tool, scene.planner, 1.5, 0.5);
  ASSERT_GT(obstacle.n_faces(), 0u);
  const double reach = std::hypot(12.0 - 3.0, 3.0) + 1.0 + 0.5;
  for (auto v : obstacle.vertices()) {
    const Eigen::Vector3d p = tf::to_eigen(obstacle.point(v));
    double nearest = 1e9;
    for (const auto& r : scene.path.rows) nearest = std::min(nearest, (r.p - p).norm());
    EXPECT_GE(nearest, reach - 1e-9);
  }
  // The post's faces toward the pass survive.
  EXPECT_GT(tf::bounding_box(obstacle).max().z(), 70.0);
}

// Only the triangles along the reach's boundary are split fine: a quarter of the edge gives about four
// times the faces (the boundary's length over the edge), not sixteen (the area over its square; a tool of
// radius 0.5 took 10.7 GB). The finer cut keeps at least the coarser one's area, and never more than the stock's.
TEST(Replan, StockObstacleGrowsWithItsBoundaryNotItsArea) {
  tf::test::TempDir dir;
  const tf::Scene scene = tf::load_scene(write_hidden_post_scene(dir));
  const tf::Mesh stock = tf::stock_to_mesh(scene.stock);
  auto area = [](const tf::Mesh& m) {
    double a = 0;
    for (auto f : m.faces()) {
      Eigen::Vector3d p[3];
      int k = 0;
      for (auto v : m.fv_range(f)) p[k++] = tf::to_eigen(m.point(v));
      a += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    }
    return a;
  };
  const tf::Mesh coarse = tf::stock_obstacle(stock, scene.path, scene.tool, scene.planner, 1.0, 0.5);
  const tf::Mesh fine = tf::stock_obstacle(stock, scene.path, scene.tool, scene.planner, 0.25, 0.5);
  ASSERT_GT(coarse.n_faces(), 0u);
  EXPECT_LT(fine.n_faces(), 6 * coarse.n_faces()) << coarse.n_faces() << " -> " << fine.n_faces();
  EXPECT_GE(area(fine), area(coarse) - 1e-6);
  EXPECT_LE(area(fine), area(stock) + 1e-6);
}

// A table that tilts 100 deg one way and 50 the other: the great circle between two axes tilted 99 deg,
// 120 deg apart round the pole, runs beyond 100 deg (no joint solution); blended in the rotaries (A held,
// C turning) every row is reached, and the ends are the old and the new axes.
TEST(Replan, BlendLeavingTheMachinesReachIsMadeInItsRotaries) {
  tf::MachineSpec m;
  m.kinematics = tf::KinematicsType::TableTableAC;
  m.limits['A'] = {-100.0, 50.0};
  const tf::Kinematics kin(m, 60.0);
  auto tilted = [](double tilt_deg, double azimuth_deg) {
    const double t = tilt_deg * M_PI / 180.0, p = azimuth_deg * M_PI / 180.0;
    return Eigen::Vector3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
  };
  const std::vector<double> weights = {0.0, 0.25, 0.5, 0.75, 1.0};
  const std::vector<Eigen::Vector3d> cl(weights.size(), Eigen::Vector3d(10, 5, 20));
  const std::vector<Eigen::Vector3d> old_axes(weights.size(), tilted(99, 0)), new_axes(weights.size(), tilted(99, 120));
  auto reached = [&](const Eigen::Vector3d& a) { return !kin.inverse(tf::ToolPose{Eigen::Vector3d(10, 5, 20) - 3.0 * a, a}, tf::Joints{}).empty(); };
  ASSERT_TRUE(reached(old_axes[0]) && reached(new_axes[0]));
  ASSERT_FALSE(reached(tf::slerp_axis(old_axes[0], new_axes[0], 0.5)));  // the great circle leaves the reach
  tf::Tool ball;
  ball.cutter = tf::BallCutter{3.0};
  const std::vector<Eigen::Vector3d> unknown(weights.size(), Eigen::Vector3d::Zero());
  const std::vector<Eigen::Vector3d> b = tf::blend_axes(cl, old_axes, new_axes, weights, ball, unknown, &kin);
  ASSERT_EQ(b.size(), weights.size());
  for (const Eigen::Vector3d& a : b) EXPECT_TRUE(reached(a)) << a.transpose();
  EXPECT_LT((b.front() - old_axes[0]).norm(), 1e-9);
  EXPECT_LT((b.back() - new_axes[0]).norm(), 1e-9);
  EXPECT_NEAR(std::acos(b[2].z()) * 180.0 / M_PI, 99.0, 1e-6);  // A held, C half-way round
  // Without a machine, and where the great circle stays within reach, it is the great circle.
  const std::vector<Eigen::Vector3d> plain = tf::blend_axes(cl, old_axes, new_axes, weights, ball, unknown, nullptr);
  EXPECT_LT((plain[2] - tf::slerp_axis(old_axes[0], new_axes[0], 0.5).normalized()).norm(), 1e-12);
}

TEST(Replan, BadVerifyReportNamesTheField) {
  tf::test::TempDir dir;
  tf::test::write_text(dir / "v.json", R"({"collisions": [{"block": 3, "line": 12, "component": "holder", "with": "stock",
    "rapid": false, "depth_mm": 0.4}]})");
  try {
    tf::read_replan_collisions(dir / "v.json");
    FAIL();
  } catch (const tf::InputError& e) {
    EXPECT_EQ(e.field(), "collisions[0].start_tip");
  }
}

}  // namespace
