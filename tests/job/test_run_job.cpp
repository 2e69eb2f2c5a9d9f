// The closed loop: a stock obstacle the check surfaces omit is found by the verifier and removed from
// the path by re-planning, without touching rows far from it.
#include <gtest/gtest.h>

#include "job.hpp"
#include "scene_writer.hpp"
#include "test_support.hpp"
#include "tiltfield/error.hpp"
#include "tiltfield/io.hpp"
#include "tiltfield/oriented_path.hpp"
#include "tiltfield/replan.hpp"
#include "tiltfield/verify.hpp"

namespace {
namespace fs = std::filesystem;

tf::Mesh box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  tf::Stock s;
  s.kind = tf::Stock::Kind::Box;
  s.box = {lo, hi};
  return tf::stock_to_mesh(s);
}

// A straight ball-end pass over a floor; the stock holds a thin layer to cut and a tall post beside the
// pass that the holder (radius 12, 60 mm above the tip) meets when the axis stays vertical. The post is
// in the stock only, not in the check surfaces, so the planner cannot know it.
fs::path write_hidden_post_scene(const tf::test::TempDir& dir) {
  tf::write_mesh(box({-50, -10, -10}, {90, 10, 0}), dir / "floor.stl");
  tf::Mesh stock = box({-50, -10, -10}, {90, 10, 0.5});
  tf::append_mesh(stock, box({15, 8, 1}, {25, 20, 80}));
  tf::write_mesh(stock, dir / "stock.stl");
  // A low wall on the far side, so the check surfaces are not empty.
  tf::write_mesh(box({-50, -22, 0}, {90, -20, 5}), dir / "wall.stl");
  std::string csv = "x,y,z,nx,ny,nz\n";
  for (int i = 0; i <= 240; ++i) csv += tf::fixed(-40 + i * 0.5, 3) + ",0,3,0,0,1\n";
  tf::test::write_text(dir / "path.csv", csv);
  tf::test::write_text(dir / "machine.json", tf::scenes::builtin_machine("table-table-ac").dump());
  tf::test::write_text(dir / "scene.json", R"({
    "design": "floor.stl", "check_surfaces": ["wall.stl"], "stock": {"mesh": "stock.stl"},
    "tool": {"type": "ball", "radius": 3, "flute_length": 12, "shank_radius": 3, "length": 60,
             "holder": [{"radius": 12, "length": 40}]},
    "path": {"file": "path.csv", "feed": 1200},
    "planner": {"safety_distance": 1.0},
    "machine": "machine.json"})");
  return dir / "scene.json";
}

TEST(RunJob, HiddenStockObstacleIsFoundAndReplannedAway) {
  tf::test::TempDir dir;
  const tf::Scene scene = tf::load_scene(write_hidden_post_scene(dir));
  tf::JobOptions options;
  options.out_dir = dir / "out";
  options.resolution_mm = 0.4;
  options.write_report = false;
  const tf::JobSummary s = tf::run_job(scene, options);
  EXPECT_GT(s.collisions_first, 0u) << tf::format_summary(s, scene);
  EXPECT_EQ(s.collisions_final, 0u) << tf::format_summary(s, scene);
  EXPECT_GE(s.rounds, 1);
  for (const char* f : {"oriented.csv", "program.ngc", "verify.json", "blocks.csv", "stock.ply"})
    EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;

  // Rows far from the post keep the planner's axis exactly: the nominal vertical axis, since the planner
  // saw no obstacle there.
  const tf::OrientedPath final_path = tf::read_oriented_csv(dir / "out" / "oriented.csv");
  ASSERT_EQ(final_path.rows.size(), scene.path.rows.size());
  EXPECT_NEAR((final_path.rows.front().axis - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-9);
  EXPECT_NEAR((final_path.rows.back().axis - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-9);
  // Next to the post the axis leans away from it (toward -y).
  const auto& mid = final_path.rows[120];  // x = 20, beside the post
  EXPECT_LT(mid.axis.y(), -0.02) << mid.axis.transpose();
}

TEST(Replan, RowsOutsideTheWindowsAreUnchangedAndEndsAreSmooth) {
  tf::test::TempDir dir;
  const tf::Scene scene = tf::load_scene(write_hidden_post_scene(dir));
  const tf::PlanOptions po =
      tf::parse_plan_options(scene.planner_json, scene.file.string(), scene.tool, scene.planner, scene.feed);
  const tf::PlanResult planned = tf::plan(scene, po);
  // A holder collision at x = 20, as the verifier would report it.
  tf::CollisionSite site;
  site.component = "holder";
  site.with = "stock";
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

TEST(Replan, BadVerifyReportNamesTheField) {
  tf::test::TempDir dir;
  tf::test::write_text(dir / "v.json", R"({"collisions": [{"block": 3, "line": 12, "component": "holder", "with": "stock"}]})");
  try {
    tf::read_collision_sites(dir / "v.json");
    FAIL();
  } catch (const tf::InputError& e) {
    EXPECT_EQ(e.field(), "collisions[0].start_tip");
  }
}

}  // namespace
