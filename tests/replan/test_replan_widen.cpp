// Re-planning widens its windows where a window planned afresh cannot be blended back clear: the rows and
// motions it leaves short are planned again on wider windows, up to the whole path.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "replan/hidden_post_scene.hpp"
#include "test_support.hpp"
#include "tilt/synthetic.hpp"
#include "tiltfield/replan/replan.hpp"

namespace {

// A 9-blade impeller planned without knowing of a 5 x 5 x 1 mm plate, then placed 15 mm up the axis of
// row 66 (black-box testing: the windows' blend turned the axis 33 degrees between two rows, through the
// plate, and left three rows in it, where a whole-path plan clears every row and motion).
TEST(ReplanWiden, AWindowThatCannotBeBlendedClearIsPlannedWider) {
  tf::test::TempDir dir;
  const std::string d = dir.path().string() + "/";
  ASSERT_EQ(tf::test::run_tiltfield("--quiet scene impeller --blades 9 --tool-radius 2 --passes 3 --ball-clearance 1.2 "
                                    "--inlet-height 30 -o " + d + "imp").exit_code, 0);
  ASSERT_EQ(tf::test::run_tiltfield("--quiet plan " + d + "imp/scene.json -o " + d + "o.csv").exit_code, 0);
  const tf::OrientedPath planned = tf::read_oriented_csv(dir / "o.csv");
  ASSERT_GT(planned.rows.size(), 66u);
  const Eigen::Vector3d centre = planned.rows[66].p + 15.0 * planned.rows[66].axis;
  tf::write_mesh(tf::test::box_mesh(centre - Eigen::Vector3d(2.5, 2.5, 0.5), centre + Eigen::Vector3d(2.5, 2.5, 0.5), 5.0),
                 dir / "imp" / "plate.stl");
  nlohmann::json j = nlohmann::json::parse(tf::test::read_text(dir / "imp" / "scene.json"));
  j["check_surfaces"].push_back("plate.stl");
  tf::test::write_text(dir / "imp" / "with_plate.json", j.dump(2));
  ASSERT_EQ(tf::test::run_tiltfield("--quiet post " + d + "imp/scene.json " + d + "o.csv -o " + d + "p.ngc").exit_code, 0);
  const auto verified = tf::test::run_tiltfield("--quiet verify " + d + "imp/with_plate.json " + d + "p.ngc -o " + d +
                                                "v.json --resolution 0.5 --no-engagement");
  ASSERT_EQ(verified.exit_code, 0) << verified.out;

  const tf::Scene scene = tf::load_scene(dir / "imp" / "with_plate.json");
  const tf::PlanOptions po =
      tf::parse_plan_options(scene.planner_json, scene.file.string(), scene.tool, scene.planner, scene.feed);
  const std::vector<tf::Collision> sites = tf::read_replan_collisions(dir / "v.json");
  ASSERT_FALSE(sites.empty());
  tf::ReplanOptions narrow;
  narrow.widen = false;
  const tf::ReplanResult first = tf::replan(scene, planned, sites, {}, po, narrow);
  ASSERT_FALSE(first.uncleared.empty() && first.uncleared_motions.empty())
      << "the windows as asked clear the plate: the scene no longer has the case this test is about";

  const tf::ReplanResult r = tf::replan(scene, planned, sites, {}, po);
  EXPECT_GE(r.widened, 1);
  EXPECT_TRUE(r.uncleared.empty()) << r.uncleared.size() << " rows";
  EXPECT_TRUE(r.uncleared_motions.empty()) << r.uncleared_motions.size() << " motions";
  // FCL is the judge: the windows' rows and the motions between them (20 poses each) keep their clearance
  // from the plate (the planner's own proofs, above, cover the blades).
  const std::vector<const tf::Mesh*> meshes = {&scene.check_surfaces.back()};
  for (const auto& w : r.windows) {
    tf::OrientedPath rows;
    rows.rows.assign(r.path.rows.begin() + long(w.first > 0 ? w.first - 1 : 0),
                     r.path.rows.begin() + long(std::min(w.last + 2, r.path.rows.size())));
    const tf::test::FclCheck check = tf::test::fcl_check(tf::test::densify(rows, 20), scene.tool, meshes, scene.planner);
    EXPECT_GE(check.min_margin, -0.02) << "window " << w.first << "-" << w.last;
  }
}

}  // namespace
