// `tiltfield plan` as a user runs it: outputs, exit codes 0 / 1 / 2, no partial output on bad input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "synthetic.hpp"
#include "tiltfield/core/oriented_path.hpp"

namespace tf {
namespace {
namespace fs = std::filesystem;

struct CliScene {
  fs::path dir;
  fs::path scene;
};

// A floor (design), a block next to the path (check surface) and the path; `planner` is the scene's
// planner object as JSON text, `y` the path's offset from the block.
CliScene write_scene(const std::string& name, const std::string& planner, double y = 0) {
  CliScene s;
  s.dir = fs::path(TILTFIELD_BINARY_DIR) / "test_plan_cli" / name;
  fs::remove_all(s.dir);
  fs::create_directories(s.dir);
  write_mesh(test::box_mesh({-10, -30, -5}, {90, 30, 0}, 20), s.dir / "floor.stl");
  write_mesh(test::box_mesh({20, 8, 0}, {60, 30, 80}, 4), s.dir / "block.stl");
  write_toolpath_csv(test::polyline_path({{0, y, 3}, {80, y, 3}}, 0.5, {0, 0, 1}), s.dir / "path.csv");
  std::ofstream(s.dir / "scene.json") << R"({"units": "mm", "design": "floor.stl", "check_surfaces": ["block.stl"],
    "stock": {"box": {"min": [-10, -30, -5], "max": [90, 30, 10]}},
    "tool": {"type": "ball", "radius": 3, "flute_length": 12, "shank_radius": 3, "length": 60,
             "holder": [{"radius": 12, "length": 40}]},
    "path": {"file": "path.csv", "feed": 1000}, "planner": )" << planner << "}\n";
  s.scene = s.dir / "scene.json";
  return s;
}

int run(const std::string& args, std::string* err = nullptr) {
  // One file per test process: ctest runs the tests of this suite side by side.
  const fs::path log = fs::path(TILTFIELD_BINARY_DIR) / "test_plan_cli" / ("stderr-" + std::to_string(::getpid()) + ".txt");
  const int rc = std::system((std::string(TILTFIELD_EXE) + " --quiet " + args + " 2> " + log.string()).c_str());
  if (err) {
    std::ifstream in(log);
    std::stringstream ss;
    ss << in.rdbuf();
    *err = ss.str();
  }
  fs::remove(log);
  return WEXITSTATUS(rc);
}

TEST(PlanCli, WritesOrientedPathAndMetrics) {
  const CliScene s = write_scene("ok", R"({"safety_distance": 1.0, "response_length_mm": 12})");
  const fs::path out = s.dir / "oriented.csv", json = s.dir / "plan.json";
  ASSERT_EQ(run("plan " + s.scene.string() + " -o " + out.string() + " --json " + json.string()), 0);
  const OrientedPath p = read_oriented_csv(out);
  EXPECT_EQ(p.rows.size(), 161u);
  for (const auto& r : p.rows) EXPECT_GE(r.clearance_mm, 1.0 - 1e-9);
  std::ifstream in(json);
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("rows").get<int>(), 161);
  EXPECT_EQ(j.at("rows_below_safety").get<int>(), 0);
  EXPECT_GT(j.at("rows_nominal_colliding").get<int>(), 0);
  for (const char* k : {"min_clearance_mm", "max_step_deg", "max_deg_per_mm", "rms_second_difference", "seconds"})
    EXPECT_TRUE(j.contains(k)) << k;
  // The baseline through the command line as well.
  ASSERT_EQ(run("plan " + s.scene.string() + " -o " + out.string() + " --method pointwise"), 0);
}

TEST(PlanCli, UnknownPlannerKeyIsBadInput) {
  const CliScene s = write_scene("badkey", R"({"safety_distance": 1.0, "repulsion_gian": 2})");
  const fs::path out = s.dir / "oriented.csv";
  std::string err;
  EXPECT_EQ(run("plan " + s.scene.string() + " -o " + out.string(), &err), 2);
  EXPECT_NE(err.find("planner.repulsion_gian"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(out));
  const CliScene t = write_scene("badvalue", R"({"influence_mm": -3})");
  EXPECT_EQ(run("plan " + t.scene.string() + " -o " + out.string(), &err), 2);
  EXPECT_NE(err.find("planner.influence_mm"), std::string::npos) << err;
  // Counts are whole numbers in range, checked before any conversion (found in review: 1e10 wrapped to a
  // negative int and switched the corrections off).
  for (const char* bad : {R"({"smooth_iterations": 1e10})", R"({"correction_iterations": 1e10})",
                          R"({"correction_iterations": 2.5})", R"({"smooth_iterations": 0})"}) {
    const CliScene u = write_scene("badcount", bad);
    EXPECT_EQ(run("plan " + u.scene.string() + " -o " + out.string(), &err), 2) << bad;
    EXPECT_NE(err.find("_iterations"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(out));
  }
}

TEST(PlanCli, UnclearableRowsExitOneAfterWriting) {
  // The path runs 3.5 mm from the block's face: the ball itself (radius 3) is inside the safety distance,
  // which no tilt can cure.
  const CliScene s = write_scene("uncleared", R"({"safety_distance": 1.0})", 4.5);
  const fs::path out = s.dir / "oriented.csv", json = s.dir / "plan.json";
  std::string err;
  EXPECT_EQ(run("plan " + s.scene.string() + " -o " + out.string() + " --json " + json.string(), &err), 1);
  EXPECT_NE(err.find("could not be cleared"), std::string::npos) << err;
  ASSERT_TRUE(fs::exists(out));
  std::ifstream in(json);
  const auto j = nlohmann::json::parse(in);
  EXPECT_GT(j.at("uncleared").size(), 0u);
  EXPECT_EQ(j.at("uncleared").size(), j.at("rows_below_safety").get<size_t>());
}

// A row no axis of the machine reaches (its normal points down, A stops at -100 deg) in a scene with no check
// surface or fixture: PLAN.json is written, its unmeasured values null (JSON has no infinity; the command had
// stopped with "fixed(): non-finite number" and no PLAN.json, black-box testing).
TEST(PlanCli, AnUnreachableRowWithoutObstaclesIsInPlanJson) {
  const fs::path dir = fs::path(TILTFIELD_BINARY_DIR) / "test_plan_cli" / "unreachable";
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_mesh(test::box_mesh({0, 0, 0}, {60, 40, 20}, 4), dir / "block.stl");
  std::ofstream(dir / "path.csv") << "x,y,z,nx,ny,nz\n10,10,19,0,0,1\n10.5,10,19,0,0,-1\n11,10,19,0,0,1\n";
  std::ofstream(dir / "machine.json")
      << R"({"kinematics": "table-table-ac", "tilt_offset": [0, 20, 10], "limits": {"A": [-100, 50]}})";
  std::ofstream(dir / "scene.json") << R"({"units": "mm", "design": "block.stl", "machine": "machine.json",
    "stock": {"box": {"min": [0, 0, 0], "max": [60, 40, 20]}},
    "tool": {"type": "flat", "radius": 4, "flute_length": 16, "shank_radius": 4, "length": 60,
             "holder": [{"radius": 12, "length": 40}]},
    "path": {"file": "path.csv", "feed": 800}, "planner": {"safety_distance": 1.0}})";
  std::string err;
  EXPECT_EQ(run("plan " + (dir / "scene.json").string() + " -o " + (dir / "o.csv").string() + " --json " +
                    (dir / "plan.json").string(),
                &err),
            1);
  EXPECT_NE(err.find("(unreachable)"), std::string::npos) << err;
  ASSERT_TRUE(fs::exists(dir / "plan.json")) << err;
  std::ifstream in(dir / "plan.json");
  const auto j = nlohmann::json::parse(in);
  ASSERT_EQ(j.at("uncleared").size(), 1u);
  EXPECT_EQ(j.at("uncleared")[0].at("row").get<int>(), 1);
  EXPECT_TRUE(j.at("uncleared")[0].at("unreachable").get<bool>());
}

// A pocket whose overhanging wall leaves the axis a band a few degrees wide, the ball 0.41 mm from the
// wall: the flutes, parallel to the wall in that band, had been asked for the whole correction margin,
// which no axis gives them, and the plan flipped the lead by 73 deg between two rows 0.5 mm apart and
// failed the motion (black-box testing). Every row and motion clears, and the axis turns smoothly.
TEST(PlanCli, FlutesBesideAnOverhangAreAskedNoMoreThanTheBall) {
  const fs::path dir = fs::path(TILTFIELD_BINARY_DIR) / "test_plan_cli" / "overhang";
  fs::remove_all(dir);
  ASSERT_EQ(run("scene pocket --overhang 35 --passes 5 --tool-radius 2 --length 40 --width 30 --wall-height 30 "
                "--ball-clearance 0.4 -o " + dir.string()),
            0);
  const fs::path json = dir / "plan.json";
  ASSERT_EQ(run("plan " + (dir / "scene.json").string() + " -o " + (dir / "o.csv").string() + " --json " + json.string()), 0);
  std::ifstream in(json);
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("segments_below_safety").get<int>(), 0);
  EXPECT_LT(j.at("max_step_deg").get<double>(), 10.0);
}

}  // namespace
}  // namespace tf
