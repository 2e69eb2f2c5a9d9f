// A real client: LinuxCNC's interpreter (rs274 -g, Debian package linuxcnc-uspace) reads every posted
// joint program; its canonical STRAIGHT_FEED output, fed back through our forward kinematics,
// reproduces the planned tool tips within 0.001 mm and the axes within 0.001 deg.
#include <gtest/gtest.h>

#include <cstdlib>
#include <regex>

#include "post_fixture.hpp"
#include "tiltfield/machine.hpp"

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

double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a;
  const double L2 = d.squaredNorm();
  const double t = L2 < 1e-300 ? 0.0 : std::clamp((p - a).dot(d) / L2, 0.0, 1.0);
  return (a + t * d - p).norm();
}

double distance_to_arc(const Eigen::Vector3d& v, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double ends = std::min(angle_deg(v, a), angle_deg(v, b));
  const Eigen::Vector3d n = a.cross(b);
  if (n.norm() < 1e-12) return ends;
  const Eigen::Vector3d u = n.normalized();
  const Eigen::Vector3d w = (v - v.dot(u) * u).normalized();
  if (std::abs(angle_deg(a, w) + angle_deg(w, b) - angle_deg(a, b)) > 1e-9) return ends;
  return std::asin(std::min(1.0, std::abs(v.dot(u)))) / kDeg;
}

// Posts `path` for `machine` through the command line and checks rs274's reading of the program.
void check_machine(const std::string& machine, const tf::OrientedPath& path) {
  TempDir dir("linuxcnc-" + machine);
  const fs::path scene = write_scene(dir.path, machine_file(machine), path);
  tf::write_oriented_csv(path, dir.path / "oriented.csv");
  const fs::path ngc = dir.path / "program.ngc";
  const auto post = run_command(std::string(TILTFIELD_EXE) + " --quiet post " + scene.string() + " " +
                                (dir.path / "oriented.csv").string() + " -o " + ngc.string() + " --dialect joint");
  ASSERT_EQ(post.exit_code, 0) << post.output;
  const auto rs = run_command("cd " + dir.path.string() + " && rs274 -g " + ngc.string());
  ASSERT_EQ(rs.exit_code, 0) << machine << ": rs274 refused the program:\n" << rs.output.substr(0, 4000);
  const Canon canon = parse_canon(rs.output);
  ASSERT_GE(canon.feeds.size(), path.rows.size()) << machine;
  EXPECT_GE(canon.traverses, 3) << machine;

  const tf::MachineSpec spec = tf::read_machine_json(machine_file(machine));
  const tf::Kinematics kin(spec, 60.0);  // the scene's gauge length
  tf::Tool tool;
  tool.cutter = tf::BallCutter{3.0};
  std::vector<Eigen::Vector3d> tips;
  for (const auto& r : path.rows) tips.push_back(tf::row_tip(r, tool));

  // The rows in order among the feed end points; every end point on the planned polyline.
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
    ASSERT_GT(row, 0u) << machine << ": a feed move before the first row";
    ASSERT_LT(row, tips.size()) << machine << ": a feed move after the last row";
    worst_line = std::max(worst_line, distance_to_segment(p.tip, tips[row - 1], tips[row]));
    worst_arc = std::max(worst_arc, distance_to_arc(p.axis, path.rows[row - 1].axis, path.rows[row].axis));
  }
  EXPECT_EQ(row, tips.size()) << machine << ": rows reproduced in order";
  EXPECT_LT(worst_line, 0.001) << machine;
  EXPECT_LT(worst_arc, 0.001) << machine;
  ::testing::Test::RecordProperty(machine + "_max_row_tip_error_mm", std::to_string(worst_row_tip));
  ::testing::Test::RecordProperty(machine + "_max_row_axis_error_deg", std::to_string(worst_row_axis));
}

TEST(LinuxCnc, Rs274ReadsJointProgramsOfEveryMachine) {
  REQUIRE_RS274();
  for (const char* m : {"table-table-ac", "table-table-bc", "head-table-bc", "head-head-ac"})
    check_machine(m, impeller_like_path(120));
  check_machine("xyz", three_axis_path(50));
}

}  // namespace
