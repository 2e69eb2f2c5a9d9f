// Re-planning widens its windows where a window planned afresh cannot be blended back clear: the rows and
// motions it leaves short are planned again on wider windows, up to the whole path.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

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

namespace {

// ASCII STL facets of the box [lo, hi], outward.
std::string box_facets(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  std::ostringstream o;
  const tf::Mesh m = tf::test::box_mesh(lo, hi, 1e9);
  for (const auto f : m.faces()) {
    o << " facet normal 0 0 0\n  outer loop\n";
    for (const auto v : m.fv_range(f)) o << "   vertex " << m.point(v)[0] << " " << m.point(v)[1] << " " << m.point(v)[2] << "\n";
    o << "  endloop\n endfacet\n";
  }
  return o.str();
}

// A vertical ball-end pass beside a tower of stock (black-box testing): the holder crashes into the tower
// for 20 mm, the verifier reports the blocks where it meets material first, and rows beyond them were
// already short before the re-plan. With --window 5 --blend 2 those rows had stayed short and the first
// attempt counted as clean (they were "already short"), so it was never widened: exit 1, a 15.7 deg step.
// A rapid's collision, which no axis fixes, is named with its reason and rows (it had been passed over:
// "0 window(s)", exit 0).
TEST(ReplanWiden, RowsShortBeforeTheReplanInTheWindowsAsAskedAreTheReplansToClear) {
  tf::test::TempDir dir;
  const std::string d = dir.path().string() + "/";
  tf::test::write_text(dir / "stock.stl", "solid s\n" + box_facets({0, 0, 0}, {60, 40, 20}) +
                                              box_facets({30, 15, 20}, {40, 25, 60}) + "endsolid s\n");
  tf::test::write_text(dir / "design.stl", "solid d\n" + box_facets({-10, -50, 17}, {29, 90, 18}) + "endsolid d\n");
  std::string path = "x,y,z,nx,ny,nz\n", oriented = "x,y,z,i,j,k,lead_deg,tilt_deg,clearance_mm\n";
  for (int k = 0; k <= 240; ++k) {
    const std::string p = "26," + std::to_string(-40.0 + 0.5 * k) + ",21";
    path += p + ",0,0,1\n";
    oriented += p + ",0,0,1,0,0,5\n";
  }
  tf::test::write_text(dir / "path.csv", path);
  tf::test::write_text(dir / "oriented.csv", oriented);
  tf::test::write_text(dir / "scene.json", R"({"units": "mm", "design": "design.stl", "stock": {"mesh": "stock.stl"},
    "tool": {"type": "ball", "radius": 3, "flute_length": 12, "shank_radius": 3, "length": 30,
             "holder": [{"radius": 12, "length": 40}]},
    "path": {"file": "path.csv", "feed": 1000}, "planner": {"lead_deg": 0, "tilt_deg": 0, "safety_distance": 1},
    "machine": ")" + std::string(TILTFIELD_SOURCE_DIR) + R"(/scenes/machines/table-table-ac.json"})");
  ASSERT_EQ(tf::test::run_tiltfield("--quiet post " + d + "scene.json " + d + "oriented.csv -o " + d + "p.ngc").exit_code, 0);
  const auto verified = tf::test::run_tiltfield("--quiet verify " + d + "scene.json " + d + "p.ngc -o " + d +
                                                "v.json --resolution 0.5 --no-engagement");
  ASSERT_EQ(verified.exit_code, 0) << verified.out;
  const auto replan = [&](const std::string& report, const std::string& options) {
    return tf::test::run_tiltfield("replan " + d + "scene.json " + d + "oriented.csv " + d + report + " -o " + d +
                                   "out.csv " + options);
  };
  const auto narrow = replan("v.json", "--window 5 --blend 2 --no-widen");
  ASSERT_EQ(narrow.exit_code, 1) << "the windows as asked clear the tower: not the case this test is about\n" << narrow.out;
  const auto widened = replan("v.json", "--window 5 --blend 2");
  EXPECT_EQ(widened.exit_code, 0) << widened.out;
  // Windows far narrower: widened past twice as wide, where it had stopped with rows still short.
  const auto tiny = replan("v.json", "--window 0.5 --blend 0.1");
  EXPECT_EQ(tiny.exit_code, 0) << tiny.out;
  // The verifier, the judge: the re-planned path's program meets no stock with its holder.
  ASSERT_EQ(tf::test::run_tiltfield("post " + d + "scene.json " + d + "out.csv -o " + d + "p2.ngc").exit_code, 0);
  ASSERT_EQ(tf::test::run_tiltfield("verify " + d + "scene.json " + d + "p2.ngc -o " + d + "v2.json --resolution 0.5 --no-engagement")
                .exit_code,
            0);
  EXPECT_TRUE(nlohmann::json::parse(tf::test::read_text(dir / "v2.json"))["collisions"].empty());

  nlohmann::json v = nlohmann::json::parse(tf::test::read_text(dir / "v.json"));
  ASSERT_FALSE(v["collisions"].empty());
  for (auto& c : v["collisions"]) c["rapid"] = true;
  tf::test::write_text(dir / "rapids.json", v.dump());
  const auto rapids = replan("rapids.json", "--quiet");
  EXPECT_EQ(rapids.exit_code, 1) << rapids.out;
  EXPECT_NE(rapids.out.find("left " + std::to_string(v["collisions"].size()) + " holder in stock (rapid), rows "),
            std::string::npos) << rapids.out;
  EXPECT_NE(rapids.out.find("no tool axis fixes"), std::string::npos) << rapids.out;
}

}  // namespace
