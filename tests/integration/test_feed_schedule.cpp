// Feed scheduling: the F-word rewrite keeps every other character; scheduled programs (G94, G93, and
// `post --max-mrr`) never exceed the MRR limit when verified again, and LinuxCNC's interpreter reads them.
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "rs274.hpp"
#include "test_support.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/engagement/feed_schedule.hpp"
#include "tiltfield/gcode/gcode.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/scene.hpp"

namespace tf {
namespace {

using test::read_text;
using test::run_tiltfield;
using test::TempDir;
using test::write_text;

// A design surface well below every cut (the CLI's scenes need one).
void write_design(const std::filesystem::path& file) {
  Stock s;
  s.kind = Stock::Kind::Box;
  s.box = {Eigen::Vector3d(-1, -21, -2), Eigen::Vector3d(101, 31, -1)};
  write_mesh(stock_to_mesh(s), file);
}

TEST(FeedSchedule, RewriteTouchesOnlyFeedWords) {
  const std::string text =
      "%\n(header F100 in a comment)\nG21 G90 G94\nG0 X-10 Y0 Z8\nG1 X30 F600 (cut F1)\ng1 x50 f 600 ; comment F7\n"
      "G1 X60\nM30\n%\n";
  const Program p = parse_gcode(text, "t.ngc", MachineSpec{});
  ASSERT_EQ(p.blocks.size(), 4u);
  FeedSchedule fs;
  fs.feed = {0.0, 300.0, 250.5, 5000.0};
  const std::string out = rewrite_feeds(text, p, fs);
  EXPECT_EQ(out,
            "%\n(header F100 in a comment)\nG21 G90 G94\nG0 X-10 Y0 Z8\nG1 X30 F300 (cut F1)\ng1 x50 F250.5 ; comment F7\n"
            "G1 X60 F5000\nM30\n%\n");
  // The rewritten text reads back with the new feeds.
  const Program q = parse_gcode(out, "t.ngc", MachineSpec{});
  EXPECT_DOUBLE_EQ(q.blocks[1].feed, 300.0);
  EXPECT_DOUBLE_EQ(q.blocks[2].feed, 250.5);
  EXPECT_DOUBLE_EQ(q.blocks[3].feed, 5000.0);
}

// A feed written as a parameter, an expression or a function is one F word as well: the rewrite replaces it
// whole ("F#1" had kept its word beside the new one, "F#1 F455.19", which LinuxCNC refuses). Parameter
// names and FIX/FUP are not F words.
TEST(FeedSchedule, RewriteReplacesParameterAndExpressionFeeds) {
  const std::string text =
      "G21 G90 G94\n#1=1000\n#<feed>=800\nG0 X-10 Y0 Z8\nG1 X10 F#1\nG1 X20 F[#1 / 2]\nG1 X30 F #<feed>\n"
      "G1 X40 F##2\nG1 X50 FABS[-700]\nG1 X[FIX[60.5]] F ATAN[1]/[1] (F9)\nG1 X70 F#[1]\nG1 X80 F#<_f> Y0\n"
      "G1 X90 F#ABS[1]\nM30\n";
  const std::string with_params = "#2=1\n#<_f>=500\n" + text;
  const Program p = parse_gcode(with_params, "t.ngc", MachineSpec{});
  ASSERT_EQ(p.blocks.size(), 10u);
  FeedSchedule fs;
  fs.feed = {0.0, 300.0, 310.0, 320.0, 330.0, 340.0, 350.0, 360.0, 370.0, 380.0};
  const std::string out = rewrite_feeds(with_params, p, fs);
  EXPECT_EQ(out,
            "#2=1\n#<_f>=500\nG21 G90 G94\n#1=1000\n#<feed>=800\nG0 X-10 Y0 Z8\nG1 X10 F300\nG1 X20 F310\n"
            "G1 X30 F320\nG1 X40 F330\nG1 X50 F340\nG1 X[FIX[60.5]] F350 (F9)\nG1 X70 F360\nG1 X80 Y0 F370\n"
            "G1 X90 F380\nM30\n");
  const Program q = parse_gcode(out, "t.ngc", MachineSpec{});
  ASSERT_EQ(q.blocks.size(), 10u);
  for (size_t i = 1; i < 10; ++i) EXPECT_DOUBLE_EQ(q.blocks[i].feed, fs.feed[i]) << i;
  EXPECT_DOUBLE_EQ(q.blocks[6].target.x, 60.0);
}

// Under G93 one F times an arc's P turns (or a spline's chords) together: unchanged blocks write back the
// same F, and a block slowed to twice its time makes the line's F as slow as that block needs.
TEST(FeedSchedule, InverseTimeLineSharesItsF) {
  const std::string text = "G21 G90 G17\nG0 X10 Y0 Z0\nG93 G3 X10 Y0 I-10 J0 P3 F2\nG94\nM30\n";
  const Program p = parse_gcode(text, "t.ngc", MachineSpec{});
  ASSERT_EQ(p.blocks.size(), 4u);  // the rapid and three turns, each a third of the minutes (F 6 each)
  FeedSchedule fs;
  for (const Block& b : p.blocks) fs.feed.push_back(b.motion == Motion::Rapid ? 0.0 : b.feed);
  EXPECT_EQ(rewrite_feeds(text, p, fs), text);
  fs.feed[2] = 3.0;  // the second turn at twice its time
  EXPECT_EQ(rewrite_feeds(text, p, fs), "G21 G90 G17\nG0 X10 Y0 Z0\nG93 G3 X10 Y0 I-10 J0 P3 F1\nG94\nM30\n");
  // A G93 line run four times (a loop) is one F for each run, not for the four together.
  const std::string loop = "G21 G91\nG0 X0 Y0 Z0\no1 repeat [4]\nG93 G1 X10 F6\no1 endrepeat\nG94\nM30\n";
  const Program l = parse_gcode(loop, "l.ngc", MachineSpec{});
  ASSERT_EQ(l.blocks.size(), 5u);
  FeedSchedule ls;
  for (const Block& b : l.blocks) ls.feed.push_back(b.motion == Motion::Rapid ? 0.0 : b.feed);
  EXPECT_EQ(rewrite_feeds(loop, l, ls), loop);
  ls.feed[3] = 3.0;  // the third run at twice its time
  EXPECT_NE(rewrite_feeds(loop, l, ls).find("G93 G1 X10 F3\n"), std::string::npos);
  // A subroutine's line run under G94 and under G93 keeps its F (schedule_feeds warns).
  const std::string mixed = "G21 G91\nG0 X0 Y0 Z0\no<s> sub\nG1 X10 F6\no<s> endsub\nG94\no<s> call\nG93\no<s> call\nG94\nM30\n";
  const Program m = parse_gcode(mixed, "m.ngc", MachineSpec{});
  ASSERT_EQ(m.blocks.size(), 3u);
  FeedSchedule ms;
  ms.feed = {0.0, 3.0, 3.0};
  EXPECT_EQ(rewrite_feeds(mixed, m, ms), mixed);
}

TEST(FeedSchedule, RejectsBadLimits) {
  FeedScheduleOptions o;
  o.max_mrr = -1.0;
  EXPECT_THROW(schedule_feeds(Program{}, VerifyReport{}, o), InputError);
  o.max_mrr = 100.0;
  o.min_feed = 0.0;
  EXPECT_THROW(schedule_feeds(Program{}, VerifyReport{}, o), InputError);
}

class ScheduleCli : public ::testing::Test {
 protected:
  void SetUp() override {
    write_design(dir / "design.stl");
    write_text(dir / "scene.json", R"({
      "units": "mm", "design": "design.stl",
      "stock": {"box": {"min": [0, -20, 0], "max": [100, 20, 10]}},
      "tool": {"type": "flat", "radius": 5, "flute_length": 20, "shank_radius": 5, "length": 40,
               "holder": [{"radius": 12, "length": 30}]},
      "path": {"file": "path.csv", "feed": 600},
      "machine": {"kinematics": "xyz", "max_feed": 5000}
    })");
    write_text(dir / "path.csv", "x,y,z,nx,ny,nz\n5,5,11,0,0,1\n");
  }
  // Verifies `program` and returns the blocks.csv rows as (line, mrr, feed-relevant cells).
  std::vector<std::vector<std::string>> blocks_of(const std::string& program) {
    const auto r = run_tiltfield("verify " + (dir / "scene.json").string() + " " + program + " -o " +
                                 (dir / "v.json").string() + " --blocks " + (dir / "b.csv").string());
    EXPECT_EQ(r.exit_code, 0) << r.out;
    std::stringstream in(read_text(dir / "b.csv"));
    std::vector<std::vector<std::string>> rows;
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
      std::vector<std::string> c;
      std::stringstream cells(line);
      for (std::string cell; std::getline(cells, cell, ',');) c.push_back(cell);
      rows.push_back(c);
    }
    return rows;
  }
  double max_mrr(const std::string& program) {
    double m = 0.0;
    for (const auto& c : blocks_of(program))
      if (c.size() > 3 && !c[3].empty()) m = std::max(m, std::stod(c[3]));
    return m;
  }
  TempDir dir;
};

// A 2 mm deep full slot (12000 mm3/min at F600), a half-width pass, a retract and an air move back.
const char* kSlot =
    "G21 G90 G94\nG0 X-10 Y0 Z8\nG1 X30 F600\nG1 X50\nG1 Y5 X90\nG1 Z15\nG1 X-10 Y10\nM30\n";

TEST_F(ScheduleCli, VerifyScheduleFeedKeepsEveryBlockUnderTheLimit) {
  write_text(dir / "p.ngc", kSlot);
  const double before = max_mrr((dir / "p.ngc").string());
  EXPECT_NEAR(before, 12000.0, 120.0);
  const auto r = run_tiltfield("verify " + (dir / "scene.json").string() + " " + (dir / "p.ngc").string() +
                               " --schedule-feed 6000 -o " + (dir / "p2.ngc").string() + " --report " +
                               (dir / "v1.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const std::string text = read_text(dir / "p2.ngc");
  const Program p2 = parse_gcode(text, "p2.ngc", MachineSpec{});
  const Program p1 = parse_gcode(read_text(dir / "p.ngc"), "p.ngc", MachineSpec{});
  ASSERT_EQ(p2.blocks.size(), p1.blocks.size());
  for (size_t i = 1; i <= 3; ++i) {  // the cutting blocks: slowed, never faster, never below the minimum
    EXPECT_LE(p2.blocks[i].feed, p1.blocks[i].feed) << "block " << i + 1;
    EXPECT_GE(p2.blocks[i].feed, 10.0) << "block " << i + 1;
  }
  EXPECT_DOUBLE_EQ(p2.blocks[4].feed, 5000.0);
  // A limit that is not positive, 0 included (black-box testing: 0 had written the report as the
  // program): exit 2 naming the option, no program.
  // The air and minimum feeds likewise, and beyond any machine's (black-box testing: --air-feed 1e300
  // wrote a 300-digit F; -1, 0 and nan had fallen back to the default without a word).
  const std::vector<std::pair<std::string, std::string>> bad_options{
      {"--schedule-feed -3", "--schedule-feed"}, {"--schedule-feed 0", "--schedule-feed"},
      {"--schedule-feed 6000 --air-feed 1e300", "--air-feed"}, {"--schedule-feed 6000 --air-feed -1", "--air-feed"},
      {"--schedule-feed 6000 --air-feed 0", "--air-feed"},    {"--schedule-feed 6000 --air-feed nan", "--air-feed"},
      {"--schedule-feed 6000 --min-feed 1e12", "--min-feed"},
      {"--schedule-feed 6000 --air-feed 5000.5", "--air-feed"},  // above the machine's max_feed
      {"--schedule-feed 6000 --air-feed inf", "--air-feed"},     // had crashed formatting the message
      {"--schedule-feed 6000 --air-feed 0.004", "--air-feed"},   // below --min-feed: had been left out silently
      {"--schedule-feed 6000 --min-feed 50 --air-feed 20", "--air-feed"}};
  for (const auto& [options, named] : bad_options) {
    const auto bad = run_tiltfield("verify " + (dir / "scene.json").string() + " " + (dir / "p.ngc").string() + " " +
                                   options + " -o " + (dir / "p3.ngc").string());
    EXPECT_EQ(bad.exit_code, 2) << options << ": " << bad.out;
    EXPECT_NE(bad.out.find(named), std::string::npos) << bad.out;
    EXPECT_EQ(test::count_lines(bad.out), 1) << bad.out;
    EXPECT_FALSE(std::filesystem::exists(dir / "p3.ngc"));
  }  // the retract and the move back cut nothing: the machine's max feed
  EXPECT_DOUBLE_EQ(p2.blocks.back().feed, 5000.0);  // the air move at the machine's max feed
  const double after = max_mrr((dir / "p2.ngc").string());
  std::cout << "max MRR " << before << " -> " << after << " mm3/min (limit 6000)\n";
  EXPECT_LE(after, 6000.0 + 0.005);
  EXPECT_GE(after, 6000.0 * 0.99);  // the limit is used, not undercut
  // A limit no block reaches leaves every cutting block's F as written, the diagonal's too (recomputed
  // from its path and time it had come back as 599.99999 and been written 599.99; black-box testing).
  ASSERT_EQ(run_tiltfield("verify " + (dir / "scene.json").string() + " " + (dir / "p.ngc").string() +
                          " --schedule-feed 1e9 -o " + (dir / "p4.ngc").string())
                .exit_code,
            0);
  const Program p4 = parse_gcode(read_text(dir / "p4.ngc"), "p4.ngc", MachineSpec{});
  for (size_t i = 1; i <= 3; ++i) EXPECT_EQ(p4.blocks[i].feed, 600.0) << "block " << i + 1;
  // Its digits too: F123.456 had been cut to F123.45.
  write_text(dir / "q.ngc", "G21 G90 G94\nG0 X-10 Y0 Z8\nG1 X30 F123.456\nM30\n");
  ASSERT_EQ(run_tiltfield("verify " + (dir / "scene.json").string() + " " + (dir / "q.ngc").string() +
                          " --schedule-feed 1e9 -o " + (dir / "q2.ngc").string())
                .exit_code,
            0);
  EXPECT_NE(read_text(dir / "q2.ngc").find("G1 X30 F123.456\n"), std::string::npos) << read_text(dir / "q2.ngc");
  TF_REQUIRE_RS274();
  const auto rs = test::run_command("cd " + dir.path().string() + " && " + test::rs274_command("p2.ngc"));
  EXPECT_EQ(rs.exit_code, 0) << rs.out.substr(0, 2000);
}

// Blocks whose feed no F on their line sets keep it: a subroutine file's (their line is the call's, where
// an F would be refused) and G33's (K per spindle turn; F is refused with it). The schedule names them.
TEST_F(ScheduleCli, FeedsOnlyWhereTheLineSetsThem) {
  write_text(dir / "slot.ngc", "o<slot> sub\nG1 X30 F600\no<slot> endsub\n");
  write_text(dir / "p.ngc", "G21 G90 G94\nG0 X-10 Y0 Z8\no<slot> call\nG0 Z15\nG0 X-10 Y5\nG0 Z8\nM3 S600\nG33 X30 K1\nM30\n");
  const auto r = run_tiltfield("verify " + (dir / "scene.json").string() + " " + (dir / "p.ngc").string() +
                               " --schedule-feed 6000 -o " + (dir / "p2.ngc").string() + " --report " +
                               (dir / "r.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_EQ(read_text(dir / "p2.ngc"), read_text(dir / "p.ngc"));  // no line could take the new feeds
  // The report keeps the schedule's warnings, not stderr alone (black-box testing).
  const std::string report_text = read_text(dir / "r.json");
  EXPECT_NE(report_text.find("feed schedule: 2 feed blocks"), std::string::npos) << report_text.substr(0, 3000);
  // The schedule names them: the same program's blocks over the limit.
  GcodeOptions options;
  options.subroutine_dirs = {dir.path()};
  const Program p = parse_gcode(read_text(dir / "p.ngc"), "p.ngc", MachineSpec{}, options);
  ASSERT_EQ(p.blocks.size(), 6u);
  VerifyReport report;
  for (size_t i = 0; i < p.blocks.size(); ++i) {
    BlockResult b;
    b.block = static_cast<int>(i) + 1;
    b.line = p.blocks[i].line;
    b.path_mm = 40.0;
    b.minutes = 40.0 / 600.0;
    b.removed_mm3 = 800.0;  // 12000 mm3/min
    report.per_block.push_back(b);
  }
  FeedScheduleOptions o;
  o.max_mrr = 6000.0;
  const FeedSchedule fs = schedule_feeds(p, report, o);
  EXPECT_TRUE(p.blocks[1].fixed_feed && p.blocks[5].fixed_feed);
  EXPECT_DOUBLE_EQ(fs.feed[1], p.blocks[1].feed);
  EXPECT_DOUBLE_EQ(fs.feed[5], p.blocks[5].feed);
  ASSERT_EQ(fs.warnings.size(), 3u);  // the two blocks, and what is not rescheduled
  EXPECT_NE(fs.warnings[2].find("2 feed blocks"), std::string::npos) << fs.warnings[2];
  EXPECT_NE(fs.warnings[0].find("(line 3)"), std::string::npos) << fs.warnings[0];
  EXPECT_NE(fs.warnings[1].find("(line 8)"), std::string::npos) << fs.warnings[1];
}

TEST_F(ScheduleCli, InverseTimeProgram) {
  write_text(dir / "p.ngc", "G21 G90\nG0 X-10 Y0 Z8\nG93 G1 X30 F15\nG1 X50 F30\nG1 Z15 F60\nG94\nM30\n");
  const auto r = run_tiltfield("verify " + (dir / "scene.json").string() + " " + (dir / "p.ngc").string() +
                               " --schedule-feed 4000 -o " + (dir / "p2.ngc").string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const double after = max_mrr((dir / "p2.ngc").string());
  std::cout << "G93: max MRR " << max_mrr((dir / "p.ngc").string()) << " -> " << after << "\n";
  EXPECT_LE(after, 4000.0 + 0.005);
  EXPECT_GE(after, 4000.0 * 0.99);
  TF_REQUIRE_RS274();
  const auto rs = test::run_command("cd " + dir.path().string() + " && " + test::rs274_command("p2.ngc"));
  EXPECT_EQ(rs.exit_code, 0) << rs.out.substr(0, 2000);
}

// A G20 program's F words are inch/min: the new feeds are written in them (black-box testing: F166.66, a
// feed in mm/min, had been written into an inch program, 25 times the limit read back).
TEST_F(ScheduleCli, InchProgramTakesItsFeedsInInches) {
  // kSlot in inches: the same cuts, F600 mm/min as F23.622.
  write_text(dir / "p.ngc", "G20 G90 G94\nG0 X-0.393701 Y0 Z0.314961\nG1 X1.181102 F23.622047\nG1 X1.968504\n"
                            "G1 Y0.19685 X3.543307\nG1 Z0.590551\nG1 X-0.393701 Y0.393701\nM30\n");
  const double before = max_mrr((dir / "p.ngc").string());
  EXPECT_NEAR(before, 12000.0, 120.0);
  const auto r = run_tiltfield("verify " + (dir / "scene.json").string() + " " + (dir / "p.ngc").string() +
                               " --schedule-feed 6000 -o " + (dir / "p2.ngc").string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const double after = max_mrr((dir / "p2.ngc").string());
  EXPECT_LE(after, 6000.0 + 0.005);
  EXPECT_GE(after, 6000.0 * 0.99);
  const Program p1 = parse_gcode(read_text(dir / "p.ngc"), "p.ngc", MachineSpec{});
  const Program p2 = parse_gcode(read_text(dir / "p2.ngc"), "p2.ngc", MachineSpec{});
  ASSERT_EQ(p2.blocks.size(), p1.blocks.size());
  for (size_t i = 1; i <= 3; ++i) EXPECT_LE(p2.blocks[i].feed, p1.blocks[i].feed + 1e-9) << "block " << i + 1;
  EXPECT_NEAR(p2.blocks.back().feed, 5000.0, 0.01);  // the air move: the machine's max feed, 196.8503 in/min
  EXPECT_NE(read_text(dir / "p2.ngc").find("F196.8503"), std::string::npos) << read_text(dir / "p2.ngc");
  // At the minimum feed, 10 mm/min is written as at least 10 (0.3937 in/min would read 9.99998).
  const auto slow = run_tiltfield("verify " + (dir / "scene.json").string() + " " + (dir / "p.ngc").string() +
                                  " --schedule-feed 1 -o " + (dir / "p3.ngc").string());
  ASSERT_EQ(slow.exit_code, 0) << slow.out;
  const std::string text = read_text(dir / "p3.ngc");
  EXPECT_NE(text.find("F0.3938"), std::string::npos) << text;
  EXPECT_EQ(text.find("F0.3937"), std::string::npos) << text;
}

// A spline's one F covers all its chords: the rewritten F keeps every chord under the limit.
TEST_F(ScheduleCli, SplineKeepsEveryChordUnderTheLimit) {
  write_text(dir / "p.ngc", "G21 G90 G17\nG0 X-10 Y0 Z8\nG5.1 X60 Y12 I35 J-25 F240\nG1 Z15\nM30\n");
  const double before = max_mrr((dir / "p.ngc").string());
  const auto r = run_tiltfield("verify " + (dir / "scene.json").string() + " " + (dir / "p.ngc").string() +
                               " --schedule-feed 3000 -o " + (dir / "p2.ngc").string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const double after = max_mrr((dir / "p2.ngc").string());
  std::cout << "spline: max MRR " << before << " -> " << after << "\n";
  EXPECT_GT(before, 3000.0);
  EXPECT_LE(after, 3000.0 + 0.005);
  EXPECT_GE(after, 3000.0 * 0.97);
}

TEST_F(ScheduleCli, PostMaxMrr) {
  // A ball-end pass 2 mm deep along x, posted with a limit.
  write_text(dir / "scene.json", R"({
      "units": "mm", "design": "design.stl",
      "stock": {"box": {"min": [0, 0, 0], "max": [40, 30, 10]}},
      "tool": {"type": "ball", "radius": 3, "flute_length": 12, "shank_radius": 3, "length": 30,
               "holder": [{"radius": 10, "length": 30}]},
      "path": {"file": "path.csv", "feed": 1200},
      "machine": {"kinematics": "xyz", "max_feed": 4000}
    })");
  std::string csv = "x,y,z,i,j,k,lead_deg,tilt_deg,clearance_mm\n";
  for (int k = 0; k <= 50; ++k) csv += std::to_string(-5.0 + k) + ",15,11,0,0,1,0,0,1\n";
  write_text(dir / "o.csv", csv);
  const std::string post = "post " + (dir / "scene.json").string() + " " + (dir / "o.csv").string() + " -o ";
  auto r = run_tiltfield(post + (dir / "p.ngc").string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const double before = max_mrr((dir / "p.ngc").string());
  const double limit = std::floor(before / 3);
  r = run_tiltfield(post + (dir / "p2.ngc").string() + " --max-mrr " + std::to_string(int(limit)));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const double after = max_mrr((dir / "p2.ngc").string());
  std::cout << "post --max-mrr: " << before << " -> " << after << " (limit " << limit << ")\n";
  EXPECT_LE(after, limit + 0.005);  // blocks.csv rounds to 0.01
  EXPECT_GE(after, limit * 0.98);
  // Bad limits, 0 included (black-box testing: 0 was taken as no limit): exit 2, one line naming the
  // option, no program written.
  for (const char* bad : {" --max-mrr -5", " --max-mrr 0"}) {
    r = run_tiltfield(post + (dir / "p3.ngc").string() + bad);
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_NE(r.out.find("--max-mrr"), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir / "p3.ngc"));
  }
  TF_REQUIRE_RS274();
  const auto rs = test::run_command("cd " + dir.path().string() + " && " + test::rs274_command("p2.ngc"));
  EXPECT_EQ(rs.exit_code, 0) << rs.out.substr(0, 2000);
}

}  // namespace
}  // namespace tf

namespace tf {
namespace {

// Mutated programs: whatever reads, the rewrite of its F words reads back to the same blocks with the
// scheduled feeds; nothing else changes.
TEST(FeedSchedule, RewriteFuzz) {
  const std::string base =
      "%\nO100 (fuzz)\nN10 G21 G90 G94 (F in a comment)\nN20 G0 X-10 Y0 Z8\nN30 G1 X30 F600 ; F7\n"
      "N40 G2 X40 Y10 I5 J5 F450\nN50 G1 Z12\nN60 G93 G1 X20 F12.5\nN70 G1 Y-4 F3\nN80 G94 G1 X0 F800\nM30\n%\n";
  const std::string alphabet = "GXYZFIJKRN0123456789.-+ ();%/\n";
  std::mt19937 rng(7);
  int checked = 0;
  for (int k = 0; k < 600; ++k) {
    std::string text = base;
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      const size_t at = rng() % text.size();
      switch (rng() % 3) {
        case 0: text.erase(at, 1); break;
        case 1: text.insert(at, 1, alphabet[rng() % alphabet.size()]); break;
        default: text[at] = alphabet[rng() % alphabet.size()];
      }
    }
    Program p;
    try {
      p = parse_gcode(text, "fuzz.ngc", MachineSpec{});
    } catch (const InputError&) {
      continue;
    }
    FeedSchedule fs;
    fs.feed.resize(p.blocks.size());
    std::map<int, int> per_line;
    for (size_t i = 0; i < p.blocks.size(); ++i) {
      fs.feed[i] = p.blocks[i].motion == Motion::Rapid ? 0.0 : 1.0 + double(rng() % 5000) / 4.0;
      ++per_line[p.blocks[i].line];
    }
    const std::string out = rewrite_feeds(text, p, fs);
    Program q;
    ASSERT_NO_THROW(q = parse_gcode(out, "fuzz.ngc", MachineSpec{})) << text << "\n---\n" << out;
    ASSERT_EQ(q.blocks.size(), p.blocks.size()) << text << "\n---\n" << out;
    for (size_t i = 0; i < p.blocks.size(); ++i) {
      EXPECT_EQ(q.blocks[i].motion, p.blocks[i].motion);
      EXPECT_NEAR(q.blocks[i].target.x, p.blocks[i].target.x, 1e-9);
      EXPECT_NEAR(q.blocks[i].target.y, p.blocks[i].target.y, 1e-9);
      // A line holding one block gets exactly its feed (lines with several take their smallest).
      if (fs.feed[i] > 0 && per_line[p.blocks[i].line] == 1) {
        EXPECT_NEAR(q.blocks[i].feed, fs.feed[i], 0.005) << out;
      }
    }
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

}  // namespace
}  // namespace tf
