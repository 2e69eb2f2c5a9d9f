// Re-planning checks the motions between its rows as the planner does: a blend that swings the holder
// through a check surface between two rows is reported, whatever the rows' own clearances say.
#include <gtest/gtest.h>

#include <algorithm>

#include "replan/hidden_post_scene.hpp"
#include "test_support.hpp"
#include "tilt/synthetic.hpp"
#include "tiltfield/replan/replan.hpp"

namespace {

// A straight pass beside a block of stock the plan does not know (x 45..55, y >= 4) and, just past it on
// the other side, a check post (x 58..62, y -14..-9): the window tilts away from the block and must turn
// back before the post (black-box testing: 27 degrees between rows 110 and 111 swept the holder through
// the post, unreported, while the window read 0.833 mm).
tf::Scene block_and_post_scene(const tf::test::TempDir& dir) {
  tf::write_mesh(tf::test::box({-20, -30, -10}, {120, 30, 0}), dir / "floor.stl");
  tf::Mesh stock = tf::test::box({-5, -25, -5}, {105, 25, 0.5});
  tf::append_mesh(stock, tf::test::box({45, 4, 0.5}, {55, 25, 70}));
  tf::write_mesh(stock, dir / "stock.stl");
  tf::write_mesh(tf::test::box({58, -14, 0}, {62, -9, 90}), dir / "post.stl");
  std::string csv = "x,y,z,nx,ny,nz\n";
  for (int i = 0; i <= 200; ++i) csv += tf::fixed(i * 0.5, 3) + ",0,3,0,0,1\n";
  tf::test::write_text(dir / "path.csv", csv);
  std::filesystem::copy_file(std::filesystem::path(TILTFIELD_SOURCE_DIR) / "scenes/machines/table-table-ac.json",
                             dir / "machine.json");
  tf::test::write_text(dir / "scene.json", R"({
    "design": "floor.stl", "check_surfaces": ["post.stl"], "stock": {"mesh": "stock.stl"}, "machine": "machine.json",
    "tool": {"type": "ball", "radius": 3, "flute_length": 12, "shank_radius": 3, "length": 60,
             "holder": [{"radius": 12, "length": 40}]},
    "path": {"file": "path.csv", "feed": 1000},
    "planner": {"safety_distance": 1.0}})");
  return tf::load_scene(dir / "scene.json");
}

TEST(ReplanMotions, AMotionThroughACheckSurfaceIsReported) {
  tf::test::TempDir dir;
  const tf::Scene scene = block_and_post_scene(dir);
  const tf::PlanOptions po =
      tf::parse_plan_options(scene.planner_json, scene.file.string(), scene.tool, scene.planner, scene.feed);
  // Planned, posted and verified as `run` does; the verifier finds the holder in the block.
  const std::string d = dir.path().string() + "/";
  for (const std::string& step : {"plan " + d + "scene.json -o " + d + "o.csv", "post " + d + "scene.json " + d + "o.csv -o " + d + "p.ngc",
                                  "verify " + d + "scene.json " + d + "p.ngc -o " + d + "v.json --resolution 0.5"}) {
    const auto run = tf::test::run_tiltfield(step);
    ASSERT_TRUE(run.exit_code == 0 || run.exit_code == 1) << step << ": " << run.out;
  }
  const tf::OrientedPath planned = tf::read_oriented_csv(dir / "o.csv");
  const std::vector<tf::Collision> sites = tf::read_replan_collisions(dir / "v.json");
  ASSERT_FALSE(sites.empty());
  const tf::Mesh obstacle = tf::stock_obstacle(tf::stock_to_mesh(scene.stock), scene.path, scene.tool, scene.planner, 1.5, 0.5);
  const tf::ReplanResult r = tf::replan(scene, planned, sites, {&obstacle}, po);
  ASSERT_FALSE(r.windows.empty());
  // FCL is the judge: every motion that comes into the post below its clearance, lower than its rows,
  // is listed.
  size_t crossings = 0;
  for (const auto& w : r.windows)
    for (size_t i = w.first > 0 ? w.first - 1 : 0; i <= w.last && i + 1 < r.path.rows.size(); ++i) {
      tf::OrientedPath rows, motion;
      rows.rows = {r.path.rows[i], r.path.rows[i + 1]};
      motion = tf::test::densify(rows, 40);
      const double row_margin = tf::test::fcl_check(rows, scene.tool, {&scene.check_surfaces[0]}, scene.planner).min_margin;
      const double motion_margin = tf::test::fcl_check(motion, scene.tool, {&scene.check_surfaces[0]}, scene.planner).min_margin;
      if (motion_margin > std::min(row_margin, 0.0) - 0.1) continue;
      ++crossings;
      const bool listed = std::any_of(r.uncleared_motions.begin(), r.uncleared_motions.end(),
                                      [&](const auto& m) { return m.first == i; });
      EXPECT_TRUE(listed) << "motion " << i << " -> " << i + 1 << ": FCL margin " << motion_margin << ", rows " << row_margin;
    }
  EXPECT_GT(crossings, 0u) << "the scene no longer has the crossing the test is about";
  for (const auto& [row, margin] : r.uncleared_motions) EXPECT_LT(margin, 0.0) << "motion from row " << row;
}

}  // namespace
