// A real client: LinuxCNC's interpreter (rs274 -g, Debian package linuxcnc-uspace) reads every posted
// joint program; its canonical STRAIGHT_FEED output, fed back through our forward kinematics,
// reproduces the planned tool tips within 0.001 mm and the axes within 0.001 deg.
#include <gtest/gtest.h>

#include <cstdlib>
#include <regex>

#include "post_fixture.hpp"
#include "rs274.hpp"
#include "tiltfield/core/machine.hpp"
#include "tiltfield/core/scene.hpp"

namespace {

using namespace post_test;

bool have_rs274() { return run_command("command -v rs274").exit_code == 0; }

#define REQUIRE_RS274()                                                                          \
  do {                                                                                           \
    if (!have_rs274()) {                                                                         \
      const char* ci = std::getenv("CI");                                                        \
      if (ci && std::string(ci) == "true") FAIL() << "rs274 (linuxcnc-uspace) is missing under CI"; \
      GTEST_SKIP() << "rs274 not installed (apt-get install linuxcnc-uspace)";                   \
    }                                                                                            \
  } while (0)

struct Canon {
  std::vector<tf::Joints> feeds;  // STRAIGHT_FEED end points, in order
  int traverses = 0;
};

Canon parse_canon(const std::string& text) {
  Canon c;
  const std::regex feed(R"(STRAIGHT_FEED\(([^)]*)\))"), trav(R"(STRAIGHT_TRAVERSE\()");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), feed); it != std::sregex_iterator(); ++it) {
    std::vector<double> v;
    std::stringstream s((*it)[1].str());
    std::string cell;
    while (std::getline(s, cell, ',')) v.push_back(std::stod(cell));
    if (v.size() < 6) continue;
    c.feeds.push_back(tf::Joints{v[0], v[1], v[2], v[3], v[4], v[5]});
  }
  c.traverses = int(std::distance(std::sregex_iterator(text.begin(), text.end(), trav), std::sregex_iterator()));
  return c;
}

// Posts `oriented` for `scene` through the command line (joint dialect), runs rs274 on the program and
// checks its STRAIGHT_FEED moves against the planned tips and axes.
void check_program(const std::string& label, const fs::path& dir, const fs::path& scene, const tf::OrientedPath& path,
                   const tf::MachineSpec& spec, const tf::Tool& tool, int min_traverses = 3) {
  tf::write_oriented_csv(path, dir / "oriented.csv");
  const fs::path ngc = dir / "program.ngc";
  const auto post = run_command(std::string(TILTFIELD_EXE) + " --quiet post " + scene.string() + " " +
                                (dir / "oriented.csv").string() + " -o " + ngc.string() + " --dialect joint");
  ASSERT_EQ(post.exit_code, 0) << post.output;
  const auto rs = run_command("cd " + dir.string() + " && " + tf::test::rs274_command(ngc.string()));
  ASSERT_EQ(rs.exit_code, 0) << label << ": rs274 refused the program:\n" << rs.output.substr(0, 4000);
  const Canon canon = parse_canon(rs.output);
  ASSERT_GE(canon.feeds.size(), path.rows.size()) << label;
  EXPECT_GE(canon.traverses, min_traverses) << label;

  const tf::Kinematics kin(spec, tool.length);
  std::vector<Eigen::Vector3d> tips;
  for (const auto& r : path.rows) tips.push_back(tf::row_tip(r, tool));

  // The rows in order among the feed end points; every other end point on the planned polyline.
  size_t row = 0;
  double worst_row_tip = 0, worst_row_axis = 0, worst_line = 0, worst_arc = 0;
  for (const tf::Joints& j : canon.feeds) {
    const tf::ToolPose p = kin.forward(j);
    if (row < tips.size() && (p.tip - tips[row]).norm() < 0.001 && angle_deg(p.axis, path.rows[row].axis) < 0.001) {
      worst_row_tip = std::max(worst_row_tip, (p.tip - tips[row]).norm());
      worst_row_axis = std::max(worst_row_axis, angle_deg(p.axis, path.rows[row].axis));
      ++row;
      continue;
    }
    ASSERT_GT(row, 0u) << label << ": a feed move before the first row";
    ASSERT_LT(row, tips.size()) << label << ": a feed move after the last row";
    worst_line = std::max(worst_line, distance_to_segment(p.tip, tips[row - 1], tips[row]));
    worst_arc = std::max(worst_arc, distance_to_arc(p.axis, path.rows[row - 1].axis, path.rows[row].axis));
  }
  EXPECT_EQ(row, tips.size()) << label << ": rows reproduced in order";
  EXPECT_LT(worst_line, 0.001) << label;
  EXPECT_LT(worst_arc, 0.001) << label;
  ::testing::Test::RecordProperty(label + "_max_row_tip_error_mm", std::to_string(worst_row_tip));
  ::testing::Test::RecordProperty(label + "_max_row_axis_error_deg", std::to_string(worst_row_axis));
}

void check_machine(const std::string& machine, const tf::OrientedPath& path, int min_traverses = 3) {
  TempDir dir("linuxcnc-" + machine);
  const fs::path scene = write_scene(dir.path, machine_file(machine), path);
  tf::Tool tool;  // as write_scene's
  tool.cutter = tf::BallCutter{3.0};
  tool.length = 60.0;
  check_program(machine, dir.path, scene, path, tf::read_machine_json(machine_file(machine)), tool, min_traverses);
}

TEST(LinuxCnc, Rs274ReadsJointProgramsOfEveryMachine) {
  REQUIRE_RS274();
  for (const char* m : {"table-table-ac", "table-table-bc", "head-table-bc", "head-head-ac"})
    check_machine(m, impeller_like_path(120));
  check_machine("xyz", three_axis_path(50));
}

// Paths with a jump (rows left out, 20 to 50 mm): the post links it (retract, rapids, approach, a feed
// plunge), with the rotaries turning on the 5-axis machines and at the lowest clear height on the xyz one;
// rs274 reads the program and the rows come out in order. Without a link a program has 3 to 5 traverses (repeated points are not written).
TEST(LinuxCnc, Rs274ReadsLinkedPrograms) {
  REQUIRE_RS274();
  auto with_jump = [](tf::OrientedPath p, int from, int to) {
    p.rows.erase(p.rows.begin() + from, p.rows.begin() + to);
    return p;
  };
  for (const char* m : {"table-table-ac", "table-table-bc", "head-table-bc", "head-head-ac"})
    check_machine(m, with_jump(impeller_like_path(120), 50, 70), 7);
  check_machine("xyz", with_jump(three_axis_path(50), 20, 32), 5);
}

// The bundled scenes (generated at build time into build/scenes/NAME/), posted with their path normals
// as tool axes (vertical for a 3-axis machine).
TEST(LinuxCnc, Rs274ReadsTheBundledScenesJointPrograms) {
  REQUIRE_RS274();
  int checked = 0;
  for (const char* name : {"impeller", "pocket", "block"}) {
    const fs::path scene_file = fs::path(TILTFIELD_BINARY_DIR) / "scenes" / name / "scene.json";
    std::error_code ec;
    if (!fs::exists(scene_file) || fs::file_size(scene_file, ec) == 0) continue;
    const tf::Scene scene = tf::load_scene(scene_file);
    ASSERT_TRUE(scene.machine) << name;
    tf::OrientedPath path;
    for (const tf::CLPoint& c : scene.path.rows) {
      tf::OrientedRow r;
      r.p = c.p;
      // A 3-axis machine keeps the axis vertical; the others take the surface normal as the axis.
      r.axis = scene.machine->kinematics == tf::KinematicsType::XYZ ? Eigen::Vector3d::UnitZ() : c.n.normalized();
      r.feed = c.feed;
      path.rows.push_back(r);
    }
    TempDir dir(std::string("bundled-") + name);
    check_program(name, dir.path, scene_file, path, *scene.machine, scene.tool);
    ++checked;
  }
  if (checked == 0) GTEST_SKIP() << "the bundled scenes are not built yet";
}

}  // namespace
