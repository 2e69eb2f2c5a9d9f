// `tiltfield post` on the command line: dialects, options, bad input (exit 2 naming the row or field).
#include <gtest/gtest.h>

#include "post_fixture.hpp"

namespace {

using namespace post_test;

struct Posted {
  CommandResult result;
  fs::path out;
};

Posted post(const TempDir& dir, const std::string& machine_json, const tf::OrientedPath& path, const std::string& args,
            const std::string& ext = "ngc") {
  const fs::path machine = dir.path / "machine.json";
  fs::copy_file(machine_json, machine, fs::copy_options::overwrite_existing);
  const fs::path scene = write_scene(dir.path, machine, path);
  tf::write_oriented_csv(path, dir.path / "oriented.csv");
  Posted p;
  p.out = dir.path / ("program." + ext);
  p.result = run_command(std::string(TILTFIELD_EXE) + " --quiet post " + scene.string() + " " +
                         (dir.path / "oriented.csv").string() + " -o " + p.out.string() + " " + args);
  return p;
}

TEST(PostCli, DialectsAndOptions) {
  TempDir dir("cli-dialects");
  const tf::OrientedPath path = impeller_like_path(30);
  auto p = post(dir, machine_file("table-table-ac").string(), path, "");
  ASSERT_EQ(p.result.exit_code, 0) << p.result.output;
  std::string text = read_text(p.out);
  EXPECT_NE(text.find("G93"), std::string::npos);  // the machine's output: joint
  EXPECT_NE(text.find("T1 M6"), std::string::npos);

  p = post(dir, machine_file("table-table-ac").string(), path, "--dialect tcp --tcp-style M128 --spindle 12000 --tool-number 7");
  ASSERT_EQ(p.result.exit_code, 0) << p.result.output;
  text = read_text(p.out);
  EXPECT_NE(text.find("\nM128\n"), std::string::npos);
  EXPECT_NE(text.find("S12000 M3"), std::string::npos);
  EXPECT_NE(text.find("T7 M6"), std::string::npos);

  p = post(dir, machine_file("table-table-ac").string(), path, "--dialect tcp");
  ASSERT_EQ(p.result.exit_code, 0) << p.result.output;
  EXPECT_NE(read_text(p.out).find("\nG43.4 H1\n"), std::string::npos);

  p = post(dir, machine_file("table-table-ac").string(), path, "--dialect apt", "apt");
  ASSERT_EQ(p.result.exit_code, 0) << p.result.output;
  EXPECT_NE(read_text(p.out).find("GOTO/"), std::string::npos);

  // Tolerance options reach the linearisation: a tighter tip tolerance gives a longer program.
  p = post(dir, machine_file("table-table-ac").string(), path, "--tip-tol 0.1 --axis-tol 1");
  ASSERT_EQ(p.result.exit_code, 0) << p.result.output;
  const size_t loose = read_text(p.out).size();
  p = post(dir, machine_file("table-table-ac").string(), path, "--tip-tol 0.001 --axis-tol 0.01 --pole-tol 0.001 --pole-mode hold");
  ASSERT_EQ(p.result.exit_code, 0) << p.result.output;
  EXPECT_GT(read_text(p.out).size(), loose);
}

TEST(PostCli, UnreachableRowExitsTwoNamingTheLine) {
  TempDir dir("cli-unreachable");
  tf::OrientedPath path = impeller_like_path(30);
  path.rows[11].axis = polar_axis(125.0, 40.0);  // beyond A -100 .. 50
  auto p = post(dir, machine_file("table-table-ac").string(), path, "");
  EXPECT_EQ(p.result.exit_code, 2) << p.result.output;
  // Header on line 1, row 12 on line 13.
  EXPECT_NE(p.result.output.find("oriented.csv:13"), std::string::npos) << p.result.output;
  EXPECT_NE(p.result.output.find("row 12"), std::string::npos) << p.result.output;
  EXPECT_NE(p.result.output.find("A limits"), std::string::npos) << p.result.output;
  EXPECT_FALSE(fs::exists(p.out));
  EXPECT_EQ(std::count(p.result.output.begin(), p.result.output.end(), '\n'), 1);
}

// Two rows within the tilt limit whose axis, turning between them along its great circle, passes beyond
// it (A limit -100; rows tilted 99.9 deg, 60 deg apart in azimuth: 101.4 deg half way): the path's fault,
// named at its row in both dialects. The tcp dialect had crashed formatting its infinite tip tolerance.
TEST(PostCli, AMoveWhoseAxisPassesBeyondATiltLimitExitsTwoNamingTheRow) {
  TempDir dir("cli-between");
  tf::OrientedPath path = impeller_like_path(2);
  path.rows[0].axis = polar_axis(99.9, 90.0);
  path.rows[1].axis = polar_axis(99.9, 150.0);
  path.rows[1].p = path.rows[0].p + Eigen::Vector3d(0.5, 0, 0);
  for (const std::string dialect : {"joint", "tcp"}) {
    auto p = post(dir, machine_file("table-table-ac").string(), path, "--dialect " + dialect);
    EXPECT_EQ(p.result.exit_code, 2) << dialect << ": " << p.result.output;
    EXPECT_NE(p.result.output.find("oriented.csv:3: row 2: the axis turning to this row along its great circle"),
              std::string::npos) << p.result.output;
    EXPECT_NE(p.result.output.find("outside the A limits [-100, 50]"), std::string::npos) << p.result.output;
    EXPECT_EQ(std::count(p.result.output.begin(), p.result.output.end(), '\n'), 1) << p.result.output;
    EXPECT_FALSE(fs::exists(p.out));
  }
}

// Small feeds keep four significant digits: the plunge at half of F0.01 had been written F0.01.
TEST(PostCli, ASmallFeedKeepsItsDigits) {
  TempDir dir("cli-small-feed");
  tf::OrientedPath path = impeller_like_path(10);
  for (size_t i = 0; i < path.rows.size(); ++i) {  // a pass of rows 0.5 mm apart: one plunge, then the cut
    path.rows[i].p = path.rows[0].p + Eigen::Vector3d(0.5 * double(i), 0, 0);
    path.rows[i].axis = Eigen::Vector3d::UnitZ();
    path.rows[i].feed = 0.01;
  }
  auto p = post(dir, machine_file("xyz").string(), path, "");
  ASSERT_EQ(p.result.exit_code, 0) << p.result.output;
  const std::string text = read_text(p.out);
  EXPECT_NE(text.find(" F0.005\n"), std::string::npos) << text.substr(0, 1500);
  EXPECT_NE(text.find(" F0.01"), std::string::npos) << text.substr(0, 1500);  // the cut
}

// A feed too small to write (it would read as F0) names its row and line (it named neither).
TEST(PostCli, FeedTooSmallToWriteExitsTwoNamingTheRow) {
  TempDir dir("cli-feed");
  const fs::path scene = write_scene(dir.path, machine_file("table-table-bc"), impeller_like_path(10));
  {
    std::ofstream csv(dir.path / "oriented.csv");
    csv << "x,y,z,i,j,k,lead_deg,tilt_deg,clearance_mm,feed\n";
    csv << "10,0,5,0,0,1,0,0,1,500\n";
    csv << "11,0,5,0,0,1,0,0,1,1e-12\n";
  }
  const fs::path out = dir.path / "p.ngc";
  const auto r = run_command(std::string(TILTFIELD_EXE) + " --quiet post " + scene.string() + " " +
                             (dir.path / "oriented.csv").string() + " -o " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("oriented.csv:3: row 2: feed 1e-12"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

// Options a controller or the method cannot use: exit 2 naming the option, no program written (found in
// review: --spindle inf crashed the number format, 1e-9 wrote S0, T0 empties LinuxCNC's spindle).
TEST(PostCli, UnusableOptionsExitTwoNamingTheOption) {
  TempDir dir("cli-options");
  const tf::OrientedPath path = impeller_like_path(10);
  for (const std::string o : {"--spindle inf", "--spindle 1e-9", "--tip-tol inf", "--axis-tol inf", "--pole-tol 60",
                               "--tool-number 0"}) {
    auto p = post(dir, machine_file("table-table-ac").string(), path, o);
    EXPECT_EQ(p.result.exit_code, 2) << o << ": " << p.result.output;
    EXPECT_NE(p.result.output.find(o.substr(0, o.find(' '))), std::string::npos) << p.result.output;
    EXPECT_FALSE(fs::exists(p.out)) << o;
  }
}

TEST(PostCli, UnknownKinematicsExitsTwoNamingTheField) {
  TempDir dir("cli-kinematics");
  {
    std::ofstream m(dir.path / "bad-machine.json");
    m << "{\"name\": \"x\", \"kinematics\": \"table-table-xy\"}\n";
  }
  auto p = post(dir, (dir.path / "bad-machine.json").string(), impeller_like_path(10), "");
  EXPECT_EQ(p.result.exit_code, 2) << p.result.output;
  EXPECT_NE(p.result.output.find("kinematics"), std::string::npos) << p.result.output;
  EXPECT_NE(p.result.output.find("table-table-xy"), std::string::npos) << p.result.output;
  EXPECT_FALSE(fs::exists(p.out));
}

TEST(PostCli, NonUnitAxisExitsTwoNamingTheRow) {
  TempDir dir("cli-axis");
  const tf::OrientedPath path = impeller_like_path(10);
  const fs::path scene = write_scene(dir.path, machine_file("table-table-bc"), path);
  {
    std::ofstream csv(dir.path / "oriented.csv");
    csv << "x,y,z,i,j,k,lead_deg,tilt_deg,clearance_mm\n";
    csv << "10,0,5,0,0,1,0,0,1\n";
    csv << "11,0,5,0,0.5,1,0,0,1\n";  // |axis| = 1.118
  }
  const fs::path out = dir.path / "p.ngc";
  const auto r = run_command(std::string(TILTFIELD_EXE) + " --quiet post " + scene.string() + " " +
                             (dir.path / "oriented.csv").string() + " -o " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("oriented.csv:3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("i,j,k"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

TEST(PostCli, BadOptionsExitTwo) {
  TempDir dir("cli-options");
  const tf::OrientedPath path = impeller_like_path(10);
  for (const char* args : {"--tip-tol 0", "--axis-tol -1", "--dialect gcode", "--tcp-style M999", "--pole-tol -0.1"}) {
    auto p = post(dir, machine_file("head-table-bc").string(), path, args);
    EXPECT_EQ(p.result.exit_code, 2) << args << ": " << p.result.output;
    EXPECT_FALSE(fs::exists(p.out)) << args;
  }
}

}  // namespace
