// The NC programs: LinuxCNC's interpreter (rs274 -g) reads the milling and ECM programs without error;
// the path in the program is the trajectory; the SVG is written.
#include <gmock/gmock.h>

#include <cstdlib>
#include <regex>

#include "offset_test_util.hpp"
#include "tiltfield/offset_program.hpp"

namespace tf::offset::test {
namespace {
namespace fs = std::filesystem;

bool have_rs274() { return std::system("command -v rs274 > /dev/null 2>&1") == 0; }

void require_rs274() {
  if (have_rs274()) return;
  const char* ci = std::getenv("CI");
  if (ci && std::string(ci) == "true") FAIL() << "rs274 (Debian package linuxcnc-uspace) is missing and CI=true";
  GTEST_SKIP() << "rs274 not installed (apt-get install linuxcnc-uspace)";
}

// Runs rs274 -g; returns its exit status and fills `log` with its output.
int run_rs274(const std::string& ngc, std::string* log) {
  const std::string out = ngc + ".rs274.txt";
  const int rc = std::system(("rs274 -g " + ngc + " > " + out + " 2>&1 < /dev/null").c_str());
  std::ifstream in(out);
  std::stringstream ss;
  ss << in.rdbuf();
  *log = ss.str();
  return WEXITSTATUS(rc);
}

int run_cli(const std::string& args) {
  return WEXITSTATUS(std::system((std::string(TILTFIELD_EXE) + " --quiet offset " + args + " 2>&1").c_str()));
}

std::string read_text(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(OffsetProgram, LinuxCncReadsMillingAndEcmPrograms) {
  require_rs274();
  const fs::path dir = fs::path(write_temp("law.csv", "s,gap\n0,0.5\n60,1.2\n150,0.8\n250,0.5\n")).parent_path();
  struct Run {
    std::string name, args;
  };
  const std::vector<Run> runs = {
      {"neck_mill", scene_file("two_lobes_neck.txt") + " -d 6"},
      {"neck_ecm", scene_file("two_lobes_neck.txt") + " -d 6 --target ecm --ecm-retract-every 40"},
      {"die_sharp", scene_file("die_section.txt") + " -d 2 --side outside --corner sharp"},
      {"blade_law_ecm", scene_file("rounded_rect.txt") + " -d 0.5 --gap-law " + (dir / "law.csv").string() +
                            " --gap-blend 3 --target ecm"},
      {"blade_mill", scene_file("blade_section.txt") + " -d 0.8 --side outside"},
  };
  for (const auto& r : runs) {
    SCOPED_TRACE(r.name);
    const fs::path ngc = dir / (r.name + ".ngc"), svg = dir / (r.name + ".svg");
    ASSERT_EQ(run_cli(r.args + " -o " + ngc.string() + " --svg " + svg.string()), 0);
    std::string log;
    EXPECT_EQ(run_rs274(ngc.string(), &log), 0) << log;
    EXPECT_THAT(log, ::testing::Not(::testing::HasSubstr("rror"))) << log;
    EXPECT_THAT(log, ::testing::HasSubstr("PROGRAM_END"));
    const std::string text = read_text(ngc);
    EXPECT_FALSE(std::regex_search(text, std::regex("[0-9][eE][-+]?[0-9]"))) << "scientific notation";
    EXPECT_THAT(read_text(svg), ::testing::HasSubstr("</svg>"));
    if (r.name.find("ecm") != std::string::npos) {
      for (const char* word : {"M8", "M9", "M64 P0", "M65 P0", "M68 E0 Q", "G4 P"})
        EXPECT_THAT(text, ::testing::HasSubstr(word));
    } else {
      EXPECT_THAT(text, ::testing::HasSubstr("M3"));
    }
  }
}

// The program's moves reproduce the trajectory: every G1/G2/G3 end point of the path lies at the gap.
TEST(OffsetProgram, ProgramPointsLieAtTheGap) {
  const Profile p = scene_profile("die_section.txt");
  const auto r = offset_profile(p, constant_gap(2.0), {});
  const auto field = make_clearance_field(p, constant_gap(2.0));
  const auto runs = plan_leads(r, *field, 2.0);
  std::ostringstream out;
  write_milling_program(out, runs, {}, {});
  std::istringstream in(out.str());
  std::string line;
  bool in_path = false;
  int checked = 0;
  const std::regex xy("^G[123] X(-?[0-9.]+) Y(-?[0-9.]+)");
  while (std::getline(in, line)) {
    if (line == "(path)") in_path = true;
    if (line == "(lead-out)") in_path = false;
    std::smatch m;
    if (in_path && std::regex_search(line, m, xy)) {
      const Eigen::Vector2d q(std::stod(m[1]), std::stod(m[2]));
      EXPECT_NEAR(profile_distance(*field, q), 2.0, 2e-6) << line;
      ++checked;
    }
  }
  EXPECT_GT(checked, 5);
  // Leads stay clear of the profile.
  for (const auto& rc : runs) {
    ASSERT_TRUE(rc.has_leads);
    for (int k = 0; k <= 20; ++k) {
      EXPECT_GE(clearance(*field, point_at(rc.lead_in, k / 20.0)), -1e-7);
      EXPECT_GE(clearance(*field, point_at(rc.lead_out, k / 20.0)), -1e-7);
    }
  }
}

TEST(OffsetProgram, EmptyOffsetIsAJobFailureWithoutOutput) {
  const fs::path dir = fs::path(write_temp("x.txt", "")).parent_path();
  const fs::path ngc = dir / "empty.ngc";
  EXPECT_EQ(run_cli(scene_file("rounded_rect.txt") + " -d 40 -o " + ngc.string()), 1);
  EXPECT_FALSE(fs::exists(ngc));
}

}  // namespace
}  // namespace tf::offset::test
