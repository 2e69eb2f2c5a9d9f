// The NC programs: LinuxCNC's interpreter (rs274 -g) reads the milling and ECM programs without error;
// the path in the program is the trajectory; the SVG is written.
#include <gmock/gmock.h>

#include <cctype>
#include <cstdlib>
#include <functional>
#include <numbers>

#include "offset_test_util.hpp"
#include "rs274.hpp"
#include "tiltfield/offset/offset_program.hpp"

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
  const int rc = std::system((tf::test::rs274_command(ngc) + " > " + out + " 2>&1 < /dev/null").c_str());
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

// Walks a program's XY moves in its path section (between "(path)" and "(lead-out)"): path_move(segment)
// for each G1/G2/G3 there (arcs with I J relative to the start), and voltage(Q) for every M67/M68 line,
// in program order.
void walk_path_moves(const std::string& text, const std::function<void(const Segment&)>& path_move,
                     const std::function<void(double)>& voltage = {}) {
  std::istringstream in(text);
  std::string line;
  bool in_path = false;
  Eigen::Vector2d cur(0, 0);
  while (std::getline(in, line)) {
    if (line == "(path)") in_path = true;
    if (line == "(lead-out)") in_path = false;
    std::istringstream words(line);
    std::string g, w;
    words >> g;
    if ((g == "M67" || g == "M68") && voltage) {
      while (words >> w)
        if (w[0] == 'Q') voltage(std::stod(w.substr(1)));
      continue;
    }
    if (g != "G0" && g != "G1" && g != "G2" && g != "G3") continue;
    Eigen::Vector2d end = cur, ij(0, 0);
    bool has_xy = false;
    while (words >> w) {
      if (w[0] == 'X') end.x() = std::stod(w.substr(1)), has_xy = true;
      if (w[0] == 'Y') end.y() = std::stod(w.substr(1)), has_xy = true;
      if (w[0] == 'I') ij.x() = std::stod(w.substr(1));
      if (w[0] == 'J') ij.y() = std::stod(w.substr(1));
    }
    if (!has_xy) continue;
    if (in_path && g != "G0") path_move(g == "G1" ? make_line(cur, end) : make_arc_to(cur, end, cur + ij, g == "G3"));
    cur = end;
  }
}

TEST(OffsetProgram, LinuxCncReadsMillingAndEcmPrograms) {
  require_rs274();
  if (IsSkipped() || HasFatalFailure()) return;  // the helper's skip or failure ends only the helper
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
    for (size_t k = 1; k + 1 < text.size(); ++k)  // no scientific notation: a digit, e/E, sign or digit
      if ((text[k] == 'e' || text[k] == 'E') && std::isdigit(static_cast<unsigned char>(text[k - 1])) &&
          (std::isdigit(static_cast<unsigned char>(text[k + 1])) || text[k + 1] == '-' || text[k + 1] == '+'))
        ADD_FAILURE() << "scientific notation near: " << text.substr(k - 1, 12);
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
  while (std::getline(in, line)) {
    if (line == "(path)") in_path = true;
    if (line == "(lead-out)") in_path = false;
    std::istringstream words(line);
    std::string g, x, y;
    words >> g >> x >> y;
    if (in_path && (g == "G1" || g == "G2" || g == "G3") && x.size() > 1 && x[0] == 'X' && y.size() > 1 && y[0] == 'Y') {
      const Eigen::Vector2d q(std::stod(x.substr(1)), std::stod(y.substr(1)));
      EXPECT_NEAR(profile_distance(*field, q), 2.0, 1e-7) << line;
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

// A lead of 128 mm in a 40 x 20 rectangle: its quarter arc, checked at 17 points, crossed the wall between
// two of them (black-box testing). Halved until clear, it keeps the gap all along: every micrometre of it.
TEST(OffsetProgram, ALongLeadIsHalvedUntilItClearsTheProfileAllAlong) {
  const Profile p = parse_profile("START 0 0\n0 40 0\n0 0 20\n0 -40 0\n0 0 -20\n", "rect");
  const auto r = offset_profile(p, constant_gap(2.0), {});
  const auto field = make_clearance_field(p, constant_gap(2.0));
  for (const double lead : {2.0, 100.0, 128.0, 1000.0}) {
    for (const auto& rc : plan_leads(r, *field, lead)) {
      ASSERT_TRUE(rc.has_leads) << lead;
      for (const Segment& s : {rc.lead_in, rc.lead_out}) {
        const int n = static_cast<int>(std::ceil(length(s) / 1e-3));
        double worst = INFINITY;
        for (int k = 0; k <= n; ++k) worst = std::min(worst, profile_distance(*field, point_at(s, double(k) / n)));
        EXPECT_GE(worst, 2.0 - 1e-6) << "lead " << lead << ", radius " << s.r;
      }
    }
  }
}

// Reads the program's path moves back (G1 lines, G2/G3 arcs with I J relative to the start) and samples
// them: every sampled point of the path lies at the gap from the profile.
TEST(OffsetProgram, ProgramMovesSampledLieAtTheGap) {
  for (const char* name : {"two_lobes_neck.txt", "die_section.txt", "blade_section.txt"}) {
    SCOPED_TRACE(name);
    const Profile p = scene_profile(name);
    const double gap = 2.5;
    for (Side side : {Side::Inside, Side::Outside}) {
      OffsetOptions o;
      o.side = side;
      const auto r = offset_profile(p, constant_gap(gap), o);
      const auto field = make_clearance_field(p, constant_gap(gap));
      std::ostringstream out;
      write_milling_program(out, plan_leads(r, *field, 2.0), {}, {});
      double worst = 0;
      int moves = 0;
      walk_path_moves(out.str(), [&](const Segment& s) {
        for (int k = 0; k <= 32; ++k)
          worst = std::max(worst, std::abs(profile_distance(*field, point_at(s, k / 32.0)) - gap));
        ++moves;
      });
      EXPECT_GE(moves, 3);
      EXPECT_LE(worst, 1e-6);
    }
  }
}

// Under a gap law the voltage follows the gap: at both ends of every path move, the set-point in force over
// the gap there (the law's value at the closest profile point) is the nominal U/g within 0.5 %. A line whose
// gap changed along it kept one set-point for its middle (41 % off at its ends; found by a helper).
TEST(OffsetProgram, EcmVoltageFollowsTheGapAlongEveryMove) {
  const Profile p = scene_profile("rounded_rect.txt");
  GapLaw law;
  law.s = {0, 60, 150, 250};
  law.gap = {0.5, 1.2, 0.8, 0.5};
  const auto r = offset_profile(p, law, {});
  const auto field = make_clearance_field(p, law);
  EcmOptions o;
  o.gap = 0.5;
  o.voltage = 12;
  std::ostringstream out;
  write_ecm_program(out, plan_leads(r, *field, 2.0), {}, o);
  double q = 0, worst = 0;
  int moves = 0;
  auto ratio_error = [&](const Eigen::Vector2d& x) {
    double sc = 0;
    profile_distance(*field, x, &sc);
    return std::abs(q / gap_at(law, sc) / (o.voltage / o.gap) - 1);
  };
  walk_path_moves(
      out.str(),
      [&](const Segment& s) {
        worst = std::max({worst, ratio_error(s.a), ratio_error(s.b)});
        ++moves;
      },
      [&](double v) { q = v; });
  EXPECT_GT(moves, 20);
  EXPECT_LE(worst, 0.005 + 1e-6);  // the writer's bound; the law at the closest point matches the move's gap to 1e-9
}

TEST(OffsetProgram, EmptyOffsetIsAJobFailureWithoutOutput) {
  const fs::path dir = fs::path(write_temp("x.txt", "")).parent_path();
  const fs::path ngc = dir / "empty.ngc";
  EXPECT_EQ(run_cli(scene_file("rounded_rect.txt") + " -d 40 -o " + ngc.string()), 1);
  EXPECT_FALSE(fs::exists(ngc));
}

TEST(OffsetProgram, OptionsThatBreakTheProgramAreBadInput) {
  // Each gave exit 0 and a program LinuxCNC refuses (a zero feed, a negative dwell or spindle speed) or one
  // that drives the tool into the part (rapids below the cutting plane, a "retract" downward); NaN gave
  // exit 1 and a message naming no option (found in review).
  const fs::path dir = fs::path(write_temp("x.txt", "")).parent_path();
  const fs::path ngc = dir / "bad.ngc";
  for (const char* opt :
       {"--plunge-feed 0", "--plunge-feed -5", "--spindle -100", "--target ecm --ecm-flush -1",
        "--z-cut 10 --z-safe 5", "--target ecm --ecm-retract-every 5 --ecm-retract-height -3", "--feed nan",
        "--z-safe nan", "--lead inf",
        // written as F0 or Q0 by the 8 decimals; a retract every nanometre wrote 1.25 GB (black-box testing)
        "--feed 1e-9", "--target ecm --ecm-voltage 1e-9", "--target ecm --ecm-retract-every 1e-9"}) {
    SCOPED_TRACE(opt);
    EXPECT_EQ(run_cli(scene_file("rounded_rect.txt") + " -d 2 " + std::string(opt) + " -o " + ngc.string()), 2);
    EXPECT_FALSE(fs::exists(ngc));
  }
  // Values beyond a million are typos: a gap of 1e300 ended in exit 1 naming no option, --z-safe 1e70 was
  // written as a 63-digit number. Electrolyte codes that stop the program or drive the spindle, and a
  // --gap-blend with no law to blend, are refused too.
  for (const char* opt : {"-d 1e300 --side outside", "-d 2 --lead 1e9", "-d 2 --gap-blend 2e6", "-d 2 --z-safe 1e70",
                          "-d 2 --feed 1e300", "-d 2 --spindle 2e6", "-d 2 --target ecm --ecm-voltage 1e300",
                          "-d 2 --target ecm --ecm-flush 1e300", "-d 2 --target ecm --ecm-electrolyte-on M2",
                          "-d 2 --target ecm --ecm-electrolyte-off M30", "-d 2 --gap-blend 1",
                          // rs274 wants words with these, M64/M65 drive the generator, M99 restarts the
                          // program, M50-M53 and M200 are no switch (black-box testing)
                          "-d 2 --target ecm --ecm-electrolyte-on M64", "-d 2 --target ecm --ecm-electrolyte-on M62",
                          "-d 2 --target ecm --ecm-electrolyte-on M68", "-d 2 --target ecm --ecm-electrolyte-on M99",
                          "-d 2 --target ecm --ecm-electrolyte-off M98", "-d 2 --target ecm --ecm-electrolyte-off M50",
                          "-d 2 --target ecm --ecm-electrolyte-off M200", "-d 2 --target ecm --ecm-electrolyte-on M12",
                          // coolant codes the wrong way round or one code for both; the other target's options
                          // (black-box testing: accepted, and the electrolyte was off while machining)
                          "-d 2 --target ecm --ecm-electrolyte-on M9 --ecm-electrolyte-off M8",
                          "-d 2 --target ecm --ecm-electrolyte-off M8", "-d 2 --target ecm --ecm-electrolyte-on M101 --ecm-electrolyte-off M101",
                          "-d 2 --ecm-voltage 30", "-d 2 --target ecm --feed 900"}) {
    SCOPED_TRACE(opt);
    EXPECT_EQ(run_cli(scene_file("rounded_rect.txt") + " " + std::string(opt) + " -o " + ngc.string()), 2);
    EXPECT_FALSE(fs::exists(ngc));
  }
  EXPECT_EQ(run_cli(scene_file("rounded_rect.txt") + " -d nan -o " + ngc.string()), 2);
  EXPECT_EQ(run_cli(scene_file("rounded_rect.txt") + " -d inf -o " + ngc.string()), 2);
  EXPECT_EQ(run_cli(scene_file("rounded_rect.txt") + " -d '' -o " + ngc.string()), 2);  // read as 0 before
  EXPECT_EQ(run_cli(scene_file("rounded_rect.txt") + " -d 2 --z-cut '' -o " + ngc.string()), 2);
}

// A D shape of one long arc: with a flush every 3, 4 or 5 mm the rounded sum of the pieces stayed a hair
// below the interval, and the next piece, below an ulp of its parameter, never moved on (the command hung,
// black-box testing). `timeout` turns a hang into a failure.
TEST(OffsetProgram, EcmFlushesOnALongArcEnd) {
  const std::string profile = write_temp("dshape.txt", "START 0 0\n20 0 10 LONG\n0 0 -10\n");
  const fs::path ngc = fs::path(profile).parent_path() / "dshape.ngc";
  for (const char* every : {"3", "4", "5"}) {
    SCOPED_TRACE(every);
    const std::string cmd = "timeout 60 " + std::string(TILTFIELD_EXE) + " --quiet offset " + profile +
                            " -d 1 --target ecm --ecm-retract-every " + every + " -o " + ngc.string();
    ASSERT_EQ(WEXITSTATUS(std::system(cmd.c_str())), 0);
    const std::string text = read_text(ngc);
    size_t flushes = 0;
    for (size_t k = text.find("retract and flush"); k != std::string::npos; k = text.find("retract and flush", k + 1)) ++flushes;
    // The path is about pi 9 + 18 mm (the offset inside at 1 mm), leads included a little more.
    EXPECT_GE(flushes, size_t((std::numbers::pi * 9 + 18) / std::stod(every)) - 1);
  }
}

// Electrolyte switches LinuxCNC runs on their own are taken, in either case: M7-M9 and user codes M100-M199.
TEST(OffsetProgram, ElectrolyteCodesTheControllerRuns) {
  const fs::path dir = fs::path(write_temp("x.txt", "")).parent_path();
  const fs::path ngc = dir / "e.ngc";
  ASSERT_EQ(run_cli(scene_file("rounded_rect.txt") + " -d 2 --target ecm --ecm-electrolyte-on m7 --ecm-electrolyte-off M107 -o " +
                    ngc.string()),
            0);
  const std::string text = read_text(ngc);
  EXPECT_THAT(text, ::testing::HasSubstr("\nM7 (electrolyte on)"));
  EXPECT_THAT(text, ::testing::HasSubstr("\nM107 (electrolyte off)"));
}

// --ecm-retract-every flushes every so many mm of path, inside a long move too: the retracts had come only
// at the ends of moves, 98 mm apart on a 100 mm square asked for every 7 (black-box testing).
TEST(OffsetProgram, EcmRetractsEverySoManyMillimetres) {
  const std::string profile = write_temp("sq100.txt", "START 0 0\n0 100 0\n0 0 100\n0 -100 0\n0 0 -100\n");
  const fs::path ngc = fs::path(profile).parent_path() / "sq100.ngc";
  ASSERT_EQ(run_cli(profile + " -d 1 --target ecm --ecm-retract-every 7 -o " + ngc.string()), 0);
  std::istringstream in(read_text(ngc));
  std::string line;
  Eigen::Vector2d at(0, 0);
  bool cutting = false;  // between the generator going on and off (chords of the leads' arcs: short)
  double since = 0, longest = 0, path = 0;
  int retracts = 0;
  const auto word = [](const std::string& l, char w, double* v) {
    const size_t k = l.find(w);
    if (k == std::string::npos) return false;
    *v = std::stod(l.substr(k + 1));
    return true;
  };
  while (std::getline(in, line)) {
    if (line.rfind("M64", 0) == 0) cutting = true, since = 0;
    if (line.rfind("M65", 0) == 0) {
      cutting = false, longest = std::max(longest, since);
      if (line.find("retract") != std::string::npos) ++retracts;
    }
    double x = at.x(), y = at.y();
    const bool motion = line.rfind("G0", 0) == 0 || line.rfind("G1", 0) == 0 || line.rfind("G2", 0) == 0 ||
                        line.rfind("G3", 0) == 0 || line.rfind("X", 0) == 0 || line.rfind("Y", 0) == 0;
    if (!motion || !(word(line, 'X', &x) | word(line, 'Y', &y))) continue;
    const double d = (Eigen::Vector2d(x, y) - at).norm();
    if (cutting) since += d, path += d;
    at = {x, y};
  }
  EXPECT_GT(path, 390.0);  // the lines of the 98 x 98 inside offset, leads included
  EXPECT_LE(longest, 7.0 + 1e-6);
  EXPECT_GE(retracts, int(path / 7.0) - 1);

  // Every mm counted is path: a lead-in (a quarter circle of radius 2) longer than the interval had made
  // the first cut start behind the contour, running backwards along it (review). The moves of the path
  // add up to its 392 mm exactly.
  ASSERT_EQ(run_cli(profile + " -d 1 --target ecm --ecm-retract-every 2 -o " + ngc.string()), 0);
  std::istringstream again(read_text(ngc));
  bool on_path = false;
  double along = 0;
  at = {0, 0};
  while (std::getline(again, line)) {
    if (line == "(path)") on_path = true;
    if (line == "(lead-out)") on_path = false;
    double x = at.x(), y = at.y();
    if (!(line.rfind("G", 0) == 0 || line.rfind("X", 0) == 0 || line.rfind("Y", 0) == 0)) continue;
    if (!(word(line, 'X', &x) | word(line, 'Y', &y))) continue;
    if (on_path) along += (Eigen::Vector2d(x, y) - at).norm();
    at = {x, y};
  }
  EXPECT_NEAR(along, 392.0, 1e-6);
}

TEST(OffsetProgram, ArcsTooSmallForTheControllerGoOutAsLines) {
  // A slot 10.001 wide offset by 5: the round ends' offsets are arcs of radius 0.0005, which LinuxCNC
  // refuses as zero-radius arcs (below 0.00127 mm); they are written as lines.
  require_rs274();
  if (IsSkipped() || HasFatalFailure()) return;
  const std::string profile = write_temp("slot.txt", "START 0 0\n0 40 0\n5.0005 0 10.001\n0 -40 0\n5.0005 0 -10.001\n");
  const fs::path ngc = fs::path(profile).parent_path() / "slot.ngc";
  ASSERT_EQ(run_cli(profile + " -d 5 -o " + ngc.string()), 0);
  std::string log;
  EXPECT_EQ(run_rs274(ngc.string(), &log), 0) << log;
  EXPECT_THAT(log, ::testing::Not(::testing::HasSubstr("rror"))) << log;
  const std::string text = read_text(ngc);
  EXPECT_EQ(text.find("\nG2 "), std::string::npos) << text;
  EXPECT_EQ(text.find("\nG3 "), std::string::npos) << text;
}

}  // namespace
}  // namespace tf::offset::test
