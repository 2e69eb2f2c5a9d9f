// The post-processor as a library: linearisation, the two-solution choice along a path, the pole,
// unwinding, limits, the writers' text.
#include <gtest/gtest.h>

#include <regex>
#include <sstream>

#include "post_fixture.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/machine.hpp"
#include "tiltfield/core/toolpath.hpp"

namespace {

using namespace post_test;
using tf::Joints;
using tf::Kinematics;
using tf::ToolPose;

const char* kFiveAxisMachines[] = {"table-table-ac", "table-table-bc", "head-table-bc", "head-head-ac"};

Joints lerp(const Joints& a, const Joints& b, double s) {
  return Joints{a.x + (b.x - a.x) * s, a.y + (b.y - a.y) * s, a.z + (b.z - a.z) * s,
                a.a + (b.a - a.a) * s, a.b + (b.b - a.b) * s, a.c + (b.c - a.c) * s};
}

TEST(Post, LinearisesALargeRotaryMoveWithinTolerance) {
  for (const char* name : kFiveAxisMachines) {
    const tf::PostJob job = job_for(name);
    tf::OrientedPath path;
    tf::OrientedRow r0, r1;
    r0.p = {30, -5, 12};
    r0.axis = polar_axis(10, 20);
    r1.p = {36, 4, 14};
    r1.axis = polar_axis(45, 110);  // a large rotary change over a short move
    path.rows = {r0, r1};
    tf::PostOptions opt;
    const tf::Program prog = tf::post_program(path, job, opt);
    const Kinematics kin(job.machine, job.tool.length);
    const auto cuts = cutting_blocks(prog);
    ASSERT_GT(cuts.size(), 4u) << name;  // it had to split
    const Eigen::Vector3d a = tf::row_tip(r0, job.tool), b = tf::row_tip(r1, job.tool);
    double worst_tip = 0, worst_axis = 0;
    for (const Cut& c : cuts) {
      for (int k = 0; k <= 100; ++k) {
        const ToolPose p = kin.forward(lerp(c.from, c.to, k / 100.0));
        worst_tip = std::max(worst_tip, distance_to_segment(p.tip, a, b));
        worst_axis = std::max(worst_axis, distance_to_arc(p.axis, r0.axis, r1.axis));
      }
    }
    EXPECT_LE(worst_tip, opt.tip_tolerance_mm) << name;
    EXPECT_LE(worst_axis, opt.axis_tolerance_deg) << name;
    // The same move as one joint-linear block would leave the tolerance (so the check above can fail).
    double naive = 0;
    for (int k = 0; k <= 100; ++k)
      naive = std::max(naive, distance_to_segment(kin.forward(lerp(cuts.front().from, cuts.back().to, k / 100.0)).tip, a, b));
    EXPECT_GT(naive, 10 * opt.tip_tolerance_mm) << name;
    // Tighter tolerances give more blocks.
    tf::PostOptions tight = opt;
    tight.tip_tolerance_mm = 0.001;
    EXPECT_GT(cutting_blocks(tf::post_program(path, job, tight)).size(), cuts.size()) << name;
  }
}

TEST(Post, ImpellerLikePathStaysWithinToleranceOnEveryMachine) {
  const tf::OrientedPath path = impeller_like_path(150);
  for (const char* name : kFiveAxisMachines) {
    const tf::PostJob job = job_for(name);
    const tf::PostOptions opt;
    const tf::Program prog = tf::post_program(path, job, opt);
    const Kinematics kin(job.machine, job.tool.length);
    for (const tf::Block& b : prog.blocks) EXPECT_TRUE(kin.within_limits(b.target)) << name;
    // Every row is reached exactly, in order, and every block end lies on the row polyline.
    size_t row = 1;  // row 0 is reached by the approach plunge
    for (const Cut& c : cutting_blocks(prog)) {
      ASSERT_LT(row, path.rows.size()) << name;
      const ToolPose p = kin.forward(c.to);
      const Eigen::Vector3d a = tf::row_tip(path.rows[row - 1], job.tool), b = tf::row_tip(path.rows[row], job.tool);
      EXPECT_LT(distance_to_segment(p.tip, a, b), 1e-6) << name << " row " << row;
      if ((p.tip - b).norm() < 1e-9) {
        // The rotaries as written (4 decimals): within 0.00005 deg each, the tip exact at them.
        EXPECT_LT(angle_deg(p.axis, path.rows[row].axis), 1e-4) << name << " row " << row;
        ++row;
      }
      // Rotary steps stay small: no configuration jumps inside the cut.
      EXPECT_LT(tf::rotary_distance(c.from, c.to), 30.0) << name;
    }
    EXPECT_EQ(row, path.rows.size()) << name;
    EXPECT_TRUE(prog.warnings.empty()) << name;
  }
}

TEST(Post, ChoosesTheSolutionTheLimitsAllow) {
  // table-table-ac's A runs -100 .. 50: tilts beyond 50 deg need the negative solution.
  const tf::PostJob job = job_for("table-table-ac");
  tf::OrientedPath path;
  for (int i = 0; i < 40; ++i) {
    tf::OrientedRow r;
    r.p = {20.0 + i * 0.5, 0, 15};
    r.axis = polar_axis(20.0 + 1.5 * i, 30.0);  // 20 .. 78.5 deg
    path.rows.push_back(r);
  }
  const tf::Program prog = tf::post_program(path, job, tf::PostOptions{});
  const Kinematics kin(job.machine, job.tool.length);
  for (const tf::Block& b : prog.blocks) {
    EXPECT_TRUE(kin.within_limits(b.target));
    EXPECT_LE(b.target.a, 1e-9);  // one branch all the way, no flip half way
  }
  EXPECT_TRUE(prog.warnings.empty());
}

TEST(Post, LimitedCForcesAChangeOfConfigurationWithARetract) {
  // head-head-ac's C runs -360 .. 360; the axis circles the pole three times.
  const tf::PostJob job = job_for("head-head-ac");
  tf::OrientedPath path;
  for (int i = 0; i <= 216; ++i) {
    tf::OrientedRow r;
    r.p = {10.0 * std::cos(i * 5 * kDeg), 10.0 * std::sin(i * 5 * kDeg), 20};
    r.axis = polar_axis(30.0, i * 5.0);
    path.rows.push_back(r);
  }
  const tf::Program prog = tf::post_program(path, job, tf::PostOptions{});
  const Kinematics kin(job.machine, job.tool.length);
  for (const tf::Block& b : prog.blocks) EXPECT_TRUE(kin.within_limits(b.target));
  EXPECT_FALSE(prog.warnings.empty());
  for (const Cut& c : cutting_blocks(prog)) EXPECT_LT(tf::rotary_distance(c.from, c.to), 30.0);
}

// Rows whose axes pass the pole at `miss_deg` in a straight great circle (the tilt plane of C = 0).
tf::OrientedPath through_pole(double miss_deg, int rows) {
  tf::OrientedPath path;
  for (int i = 0; i < rows; ++i) {
    const double t = -3.0 + 6.0 * i / (rows - 1);  // deg along the great circle
    tf::OrientedRow r;
    r.p = {i * 0.2, 5, 15};
    // Tangent-plane coordinates (t, miss) around +Z, mapped onto the sphere.
    r.axis = Eigen::Vector3d(std::sin(t * kDeg), std::sin(miss_deg * kDeg), 1.0).normalized();
    path.rows.push_back(r);
  }
  return path;
}

double c_range(const tf::Program& p) {
  double lo = 1e300, hi = -1e300;
  for (const Cut& c : cutting_blocks(p)) {
    lo = std::min(lo, c.to.c);
    hi = std::max(hi, c.to.c);
  }
  return hi - lo;
}

TEST(Post, SingularPoleKeepsCFromSwinging) {
  for (const char* name : kFiveAxisMachines) {
    const tf::PostJob job = job_for(name);
    const Kinematics kin(job.machine, job.tool.length);
    tf::PostOptions opt;
    opt.pole_tolerance_deg = 0.5;
    // Straight through the pole: C does not move at all.
    EXPECT_LT(c_range(tf::post_program(through_pole(0.0, 61), job, opt)), 1e-6) << name;
    // Missing the pole by 0.2 deg, inside the 0.5 deg cone: C moves at most 2 asin(0.2 / 0.5).
    const double limit = 2.0 * std::asin(0.2 / 0.5) / kDeg;
    const tf::OrientedPath near = through_pole(0.2, 61);
    const tf::Program held = tf::post_program(near, job, opt);
    EXPECT_LE(c_range(held), limit + 0.5) << name;
    // ... and every block end keeps the axis within the pole tolerance plus the axis tolerance.
    for (const Cut& c : cutting_blocks(held)) {
      const ToolPose p = kin.forward(c.to);
      double best = 180;
      for (const auto& r : near.rows) best = std::min(best, angle_deg(p.axis, r.axis));
      EXPECT_LE(best, opt.pole_tolerance_deg + opt.axis_tolerance_deg) << name;
    }
    // Without the cone the exact solution has to swing C round by about half a turn.
    opt.pole_tolerance_deg = 0.0;
    opt.axis_tolerance_deg = 0.05;
    EXPECT_GT(c_range(tf::post_program(near, job, opt)), 90.0) << name;
  }
}

// The joints at which the program reaches each row's tip (in order).
std::vector<Joints> joints_at_rows(const tf::Program& prog, const tf::OrientedPath& path, const tf::PostJob& job) {
  const Kinematics kin(job.machine, job.tool.length);
  std::vector<Joints> out;
  for (const tf::Block& b : prog.blocks) {
    if (out.size() == path.rows.size() || b.motion != tf::Motion::Linear) continue;
    if ((kin.forward(b.target).tip - tf::row_tip(path.rows[out.size()], job.tool)).norm() < 1e-9) out.push_back(b.target);
  }
  return out;
}

// How the program's cutting blocks follow the rows in order: the rows reached (from the first), and the
// largest distance of the joint-linear tip from each row segment and of the axis from its great-circle arc.
struct Followed {
  size_t rows = 1;
  double tip_mm = 0, axis_deg = 0;
};
Followed follow_rows(const tf::Program& prog, const tf::OrientedPath& path, const tf::PostJob& job,
                     const Kinematics& kin) {
  Followed f;
  for (const Cut& c : cutting_blocks(prog)) {
    if (f.rows >= path.rows.size()) {
      ++f.rows;  // a block past the last row: counted, so that the caller's row count fails
      break;
    }
    const tf::OrientedRow &r0 = path.rows[f.rows - 1], &r1 = path.rows[f.rows];
    for (int k = 0; k <= 100; ++k) {
      const ToolPose p = kin.forward(lerp(c.from, c.to, k / 100.0));
      f.tip_mm = std::max(f.tip_mm, distance_to_segment(p.tip, tf::row_tip(r0, job.tool), tf::row_tip(r1, job.tool)));
      f.axis_deg = std::max(f.axis_deg, distance_to_arc(p.axis, r0.axis, r1.axis));
    }
    if ((kin.forward(c.to).tip - tf::row_tip(r1, job.tool)).norm() < 1e-9) ++f.rows;
  }
  return f;
}

TEST(Post, PassingNearThePoleBeyondTheTolerancesSwingsCAndStaysExact) {
  // The axis misses the pole by 1 deg, more than axis + pole tolerance: flipping to the mirror solution
  // would take the axis through the pole (1 deg off), so C has to swing, in linearised steps.
  for (const char* name : kFiveAxisMachines) {
    const tf::PostJob job = job_for(name);
    const Kinematics kin(job.machine, job.tool.length);
    tf::OrientedPath path;
    for (int i = 0; i < 9; ++i) {
      const double t = -4.0 + i;  // deg along the great circle, 1 deg rows
      tf::OrientedRow r;
      r.p = {22.0 + 0.05 * i, 27.0 + 0.4 * i, 18.0};
      r.axis = Eigen::Vector3d(std::sin(t * kDeg), std::sin(1.0 * kDeg), 1.0).normalized();
      path.rows.push_back(r);
    }
    const tf::PostOptions opt;
    const tf::Program prog = tf::post_program(path, job, opt);
    EXPECT_GT(c_range(prog), 90.0) << name;
    const Followed f = follow_rows(prog, path, job, kin);
    EXPECT_EQ(f.rows, path.rows.size()) << name;
    EXPECT_LE(f.tip_mm, opt.tip_tolerance_mm) << name;
    EXPECT_LE(f.axis_deg, opt.axis_tolerance_deg) << name;
  }
}

// A small tilt whose azimuth turns fast (0.5 deg off the pole, +137 deg a row, the great arcs between rows
// passing 0.18 deg from the pole, outside the 0.1 deg cone): the per-row choice flips the tilt's sign where
// the joints cannot follow without a retract, while staying in the present configuration (C swinging, the
// move bisected) keeps every move within the tolerances. No retract but where a limited C must unwind
// (black-box testing: 40 on 41 rows).
TEST(Post, FastAzimuthNearThePoleNeedsNoRetract) {
  for (const char* name : kFiveAxisMachines) {
    const tf::PostJob job = job_for(name);
    const Kinematics kin(job.machine, job.tool.length);
    tf::OrientedPath path;
    for (int i = 0; i < 41; ++i) {
      tf::OrientedRow r;
      r.p = {20.0 + 0.1 * i, 25.0, 18.0};
      r.axis = polar_axis(0.5, 137.0 * i);
      path.rows.push_back(r);
    }
    const tf::PostOptions opt;
    const tf::Program prog = tf::post_program(path, job, opt);
    int changes = 0;
    for (const std::string& w : prog.warnings) changes += w.find("change of configuration") != std::string::npos;
    // C follows the azimuth, 40 x 137 deg: a C limited to [min, max] unwinds once per max - min of it.
    const auto c_limit = job.machine.limits.find('C');
    const int unwinds = c_limit == job.machine.limits.end() ? 0 : int(40 * 137.0 / (c_limit->second.max - c_limit->second.min));
    EXPECT_LE(changes, unwinds) << name;
    const Followed f = follow_rows(prog, path, job, kin);
    EXPECT_EQ(f.rows, path.rows.size()) << name;
    EXPECT_LE(f.tip_mm, opt.tip_tolerance_mm) << name;
    EXPECT_LE(f.axis_deg, opt.axis_tolerance_deg + opt.pole_tolerance_deg) << name;
  }
}

TEST(Post, PoleModeHoldOrInterpolate) {
  // The axis comes in leaning toward +X, passes the pole and leaves leaning toward +Y: C must turn
  // 90 deg, and the rows inside the pole cone decide how.
  const tf::PostJob job = job_for("table-table-ac");
  tf::OrientedPath path;
  for (int i = 0; i <= 40; ++i) {
    const double t = i / 40.0;
    tf::OrientedRow r;
    r.p = {t * 8.0, 0, 15};
    r.axis = t < 0.5 ? polar_axis(1.0 - 2.0 * t, 0.0) : polar_axis(2.0 * t - 1.0, 90.0);
    path.rows.push_back(r);
  }
  tf::PostOptions opt;
  opt.pole_tolerance_deg = 0.3;
  const Kinematics kin(job.machine, job.tool.length);
  for (auto mode : {tf::PoleMode::Interpolate, tf::PoleMode::Hold}) {
    opt.pole_mode = mode;
    const std::vector<Joints> j = joints_at_rows(tf::post_program(path, job, opt), path, job);
    ASSERT_EQ(j.size(), path.rows.size());
    std::vector<size_t> cone;
    for (size_t i = 0; i < path.rows.size(); ++i) {
      EXPECT_LE(angle_deg(kin.forward(j[i]).axis, path.rows[i].axis), opt.pole_tolerance_deg + 1e-9);
      if (Kinematics::pole_angle_deg(path.rows[i].axis) < opt.pole_tolerance_deg) cone.push_back(i);
    }
    ASSERT_GE(cone.size(), 5u);
    const double before = j[cone.front() - 1].c, after = j[cone.back() + 1].c;
    EXPECT_NEAR(std::abs(after - before), 90.0, 1.0);
    for (size_t k = 0; k < cone.size(); ++k) {
      const double c = j[cone[k]].c;
      if (mode == tf::PoleMode::Hold) {
        EXPECT_EQ(c, before);
      } else {
        // Strictly between, moving monotonically from the value before to the value after.
        EXPECT_GT((c - before) * (after - before), 0.0);
        EXPECT_GT((after - c) * (after - before), 0.0);
        if (k > 0) {
          EXPECT_GT((c - j[cone[k - 1]].c) * (after - before), 0.0);
        }
      }
    }
  }
}

TEST(Post, ZLimitShortensTransitsInsteadOfFailing) {
  tf::PostJob job = job_for("table-table-ac");
  job.machine.limits['Z'] = {-500.0, 160.0};
  const tf::OrientedPath path = impeller_like_path(40);
  const tf::Program prog = tf::post_program(path, job, tf::PostOptions{});
  const Kinematics kin(job.machine, job.tool.length);
  for (const tf::Block& b : prog.blocks) EXPECT_TRUE(kin.within_limits(b.target));
  EXPECT_FALSE(prog.warnings.empty());
  EXPECT_NEAR(prog.start.z, 160.0, 1e-9);
}

TEST(Post, UnreachableRowIsNamed) {
  tf::PostJob job = job_for("table-table-ac");
  tf::OrientedPath path = impeller_like_path(20);
  path.rows[7].axis = polar_axis(120.0, 10.0);  // beyond A's -100 .. 50 either way
  try {
    tf::post_program(path, job, tf::PostOptions{});
    FAIL() << "no error";
  } catch (const tf::PostRowError& e) {
    EXPECT_EQ(e.row(), 7u);
    EXPECT_NE(std::string(e.what()).find("A limits"), std::string::npos) << e.what();
  }
  // Just past a limit, the angle reads past it (black-box testing: "needs A = +-100" for -100.000005).
  path.rows[7].axis = polar_axis(100.000005, 10.0);
  try {
    tf::post_program(path, job, tf::PostOptions{});
    FAIL() << "no error";
  } catch (const tf::PostRowError& e) {
    EXPECT_NE(std::string(e.what()).find("+-100.000005"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("+-100 deg"), std::string::npos) << e.what();
  }
  // The 3-axis machine refuses a tilted axis.
  job = job_for("xyz");
  try {
    tf::post_program(path, job, tf::PostOptions{});
    FAIL() << "no error";
  } catch (const tf::PostRowError& e) {
    EXPECT_EQ(e.row(), 0u);
  }
}

TEST(Post, JointTextHasInverseTimeAndNoScientificNotation) {
  const tf::PostJob job = job_for("table-table-bc");
  tf::PostOptions opt;
  const tf::OrientedPath path = impeller_like_path(60);
  std::ostringstream s;
  tf::write_gcode(s, tf::post_program(path, job, opt), job, opt);
  const std::string text = s.str();
  EXPECT_FALSE(std::regex_search(text, std::regex(R"([0-9][eE][-+]?[0-9])")));
  EXPECT_TRUE(std::regex_search(text, std::regex(R"(\nG93 G1 [^\n]* F[0-9.]+\n)")));
  EXPECT_NE(text.find("T1 M6"), std::string::npos);
  EXPECT_NE(text.find("S10000 M3"), std::string::npos);
  EXPECT_NE(text.find("G21"), std::string::npos);
  EXPECT_EQ(text.find(" A"), std::string::npos);  // a B-C machine writes no A words
  // Every G1 in inverse-time mode carries F.
  std::istringstream lines(text);
  std::string line;
  bool inverse = false;
  while (std::getline(lines, line)) {
    if (line.find("G93") != std::string::npos) inverse = true;
    if (line.find("G94") != std::string::npos) inverse = false;
    if (inverse && (line.rfind("G1", 0) == 0 || line.find(" G1") != std::string::npos)) {
      EXPECT_NE(line.find(" F"), std::string::npos) << line;
    }
  }
}

TEST(Post, TcpDialectWritesTipsWithTheTcpCode) {
  const tf::PostJob job = job_for("head-head-ac");
  const tf::OrientedPath path = impeller_like_path(40);
  for (auto style : {tf::TcpStyle::G43_4, tf::TcpStyle::M128}) {
    tf::PostOptions opt;
    opt.dialect = tf::Dialect::Tcp;
    opt.tcp_style = style;
    const tf::Program prog = tf::post_program(path, job, opt);
    // Every row's tip is a block target; tcp blocks only split for the axis.
    size_t found = 0;
    for (const auto& r : path.rows) {
      const Eigen::Vector3d tip = tf::row_tip(r, job.tool);
      for (const tf::Block& b : prog.blocks)
        if (b.tcp && (Eigen::Vector3d(b.target.x, b.target.y, b.target.z) - tip).norm() < 1e-9) {
          ++found;
          break;
        }
    }
    EXPECT_EQ(found, path.rows.size());
    std::ostringstream s;
    tf::write_gcode(s, prog, job, opt);
    const std::string text = s.str();
    if (style == tf::TcpStyle::G43_4) {
      EXPECT_NE(text.find("\nG43.4 H1\n"), std::string::npos);
      EXPECT_NE(text.find("\nG49\nM5"), std::string::npos);
    } else {
      // The M code's TCP tracks the tip only with the tool length offset in force.
      EXPECT_NE(text.find("\nM128\nG43 H1\n"), std::string::npos);
      EXPECT_NE(text.find("\nM129\nG49\nM5"), std::string::npos);
    }
    EXPECT_EQ(text.find("G93"), std::string::npos);
  }
}

// A C axis whose limits lie turns away from 0 still offers the turn inside them (found in review: only
// three turns either side were tried), and a tiny feed is written with the places it needs, never F0.
TEST(Post, FarCLimitsAndTinyFeeds) {
  tf::PostJob job = job_for("head-head-ac");
  job.machine.limits['C'] = {1450.0, 1800.0};
  tf::OrientedPath path = impeller_like_path(10);
  for (auto& r : path.rows) r.feed = 0.004;
  tf::PostOptions opt;
  const tf::Program prog = tf::post_program(path, job, opt);
  std::ostringstream s;
  tf::write_gcode(s, prog, job, opt);
  EXPECT_EQ(s.str().find("F0\n"), std::string::npos) << s.str();
  EXPECT_EQ(s.str().find("F0.00\n"), std::string::npos);
  // Every C the program writes lies inside the limits (the first retract moves Z only).
  const std::regex c_word(R"(C(-?[0-9.]+))");
  int written = 0;
  const std::string text = s.str();
  for (auto it = std::sregex_iterator(text.begin(), text.end(), c_word); it != std::sregex_iterator(); ++it) {
    const double c = std::stod((*it)[1].str());
    EXPECT_GE(c, 1450.0 - 1e-4);
    EXPECT_LE(c, 1800.0 + 1e-4);
    ++written;
  }
  EXPECT_GT(written, 0);
}

// Three turns of a spiral on a C limited to a turn either way need one change of configuration, not two
// unwinds (found in review: an unwind was priced as C motion, the flip that would do it with one retract as
// a retract).
// A head tilted far from vertical rises straight up from its full retract: rising on along the axis had
// carried it 2.3 m sideways on an 84 deg axis, beyond the machine's X and Y (found in review). The part
// lies behind the plane through the retracted tip normal to the axis, and a rise straight up leaves it.
TEST(Post, FarTiltedHeadRisesStraightUpToTheTransitHeight) {
  tf::PostJob job = job_for("head-head-ac");
  job.machine.limits['X'] = {-300.0, 300.0};
  job.machine.limits['Y'] = {-300.0, 300.0};
  tf::OrientedPath path;
  for (int i = 0; i <= 20; ++i) {
    tf::OrientedRow r;
    r.p = {40.0 + i, 0.0, 10.0};
    r.axis = polar_axis(80.0, 0.0);
    path.rows.push_back(r);
  }
  const tf::Program prog = tf::post_program(path, job, tf::PostOptions{});
  const Kinematics kin(job.machine, job.tool.length);
  for (const tf::Block& b : prog.blocks) EXPECT_TRUE(kin.within_limits(b.target)) << b.target.x << " " << b.target.y;
  // The last two rapids: along the axis to the retract, then straight up.
  ASSERT_GE(prog.blocks.size(), 3u);
  const tf::Joints& retract = prog.blocks[prog.blocks.size() - 2].target;
  const tf::Joints& high = prog.blocks.back().target;
  EXPECT_DOUBLE_EQ(high.x, retract.x);
  EXPECT_DOUBLE_EQ(high.y, retract.y);
  EXPECT_GT(high.z, retract.z);
}

TEST(Post, OneRetractWhereOneDoes) {
  const tf::PostJob job = job_for("head-head-ac");
  tf::OrientedPath path;
  for (int i = 0; i <= 216; ++i) {
    const double phi = 5.0 * i * kDeg;
    tf::OrientedRow r;
    r.p = {5.0 * std::cos(phi), 5.0 * std::sin(phi), 3.0};
    r.axis = polar_axis(30.0, 5.0 * i);
    path.rows.push_back(r);
  }
  const tf::Program prog = tf::post_program(path, job, tf::PostOptions{});
  int changes = 0;
  for (const std::string& w : prog.warnings) changes += w.find("change of configuration") != std::string::npos;
  EXPECT_EQ(changes, 1);
}

// A machine's own TCP codes (LinuxCNC's switchkins: M428, M429) come with G43 H, as LinuxCNC's boat demo
// writes them: under G49 the controller would track the spindle nose and run the tip a gauge length deep.
// The codes come in pairs.
TEST(Post, MachineTcpCodeComesWithTheToolLengthOffset) {
  tf::PostJob job = job_for("head-head-ac");
  job.machine.tcp_on_code = "M428";
  job.machine.tcp_off_code = "M429";
  tf::PostOptions opt;
  opt.dialect = tf::Dialect::Tcp;
  const tf::Program prog = tf::post_program(impeller_like_path(10), job, opt);
  std::ostringstream s;
  tf::write_gcode(s, prog, job, opt);
  EXPECT_NE(s.str().find("\nM428\nG43 H1\n"), std::string::npos) << s.str();
  EXPECT_NE(s.str().find("\nM429\nG49\nM5"), std::string::npos);  // and the G43 cancelled
  try {
    tf::parse_machine_json(nlohmann::json{{"name", "m"}, {"kinematics", "table-table-ac"}, {"tcp_on_code", "M428"}},
                           "m.json", "");
    ADD_FAILURE() << "tcp_on_code without tcp_off_code accepted";
  } catch (const tf::InputError& e) {
    EXPECT_EQ(e.field(), "tcp_off_code");
  }
}

TEST(Post, AptWritesTipsAndAxes) {
  const tf::PostJob job = job_for("table-table-ac");
  const tf::OrientedPath path = impeller_like_path(100);  // rows about 3 mm apart: no link
  std::ostringstream s;
  tf::PostOptions opt;
  tf::write_apt(s, path, job, opt);
  const std::string text = s.str();
  EXPECT_NE(text.find("MULTAX/ON"), std::string::npos);
  EXPECT_NE(text.find("FEDRAT/1500,MMPM"), std::string::npos);
  EXPECT_NE(text.find("CUTTER/6,3"), std::string::npos);
  std::regex go(R"(GOTO/(-?[0-9.]+),(-?[0-9.]+),(-?[0-9.]+),(-?[0-9.]+),(-?[0-9.]+),(-?[0-9.]+))");
  std::vector<std::array<double, 6>> gotos;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), go); it != std::sregex_iterator(); ++it) {
    std::array<double, 6> v;
    for (int k = 0; k < 6; ++k) v[k] = std::stod((*it)[k + 1]);
    gotos.push_back(v);
  }
  ASSERT_EQ(gotos.size(), path.rows.size() + 2);  // approach, rows, retract
  for (size_t i = 0; i < path.rows.size(); ++i) {
    const Eigen::Vector3d tip = tf::row_tip(path.rows[i], job.tool);
    EXPECT_NEAR(gotos[i + 1][0], tip.x(), 1e-4);
    EXPECT_NEAR(gotos[i + 1][2], tip.z(), 1e-4);
    EXPECT_NEAR(gotos[i + 1][5], path.rows[i].axis.z(), 1e-6);
  }
}

// A jump between rows is linked, not cut through (found in review: a 28 mm feed at cutting depth): the
// retract above the last row, the rapid to above the next, then its GOTO.
TEST(Post, AptLinksAJumpBetweenRows) {
  const tf::PostJob job = job_for("table-table-ac");
  tf::OrientedPath path = impeller_like_path(100);
  for (size_t i = 10; i < path.rows.size(); ++i) path.rows[i].p.x() += 40.0;
  std::ostringstream s;
  tf::PostOptions opt;
  tf::write_apt(s, path, job, opt);
  const std::string text = s.str();
  size_t rapids = 0;
  for (size_t at = text.find("RAPID\n"); at != std::string::npos; at = text.find("RAPID\n", at + 1)) ++rapids;
  EXPECT_EQ(rapids, 4u);  // approach, the link's retract and rapid, the final retract
  // The link sits between rows 10 and 11: the two RAPID points lie above the part, not on the path.
  const size_t link = text.find("RAPID\n", text.find("RAPID\n") + 1);
  ASSERT_NE(link, std::string::npos);
  std::regex go(R"(GOTO/(-?[0-9.]+),(-?[0-9.]+),(-?[0-9.]+))");
  std::smatch m;
  const std::string after = text.substr(link);
  ASSERT_TRUE(std::regex_search(after, m, go));
  // Up row 9's axis from its tip, at least safe_z (beyond the part's extent along the axis).
  const Eigen::Vector3d point(std::stod(m[1]), std::stod(m[2]), std::stod(m[3]));
  const Eigen::Vector3d from = point - tf::row_tip(path.rows[9], job.tool), axis = path.rows[9].axis.normalized();
  EXPECT_GT(from.dot(axis), job.machine.safe_z - 1e-3);
  EXPECT_LT(from.cross(axis).norm(), 1e-3);
}

TEST(Post, AptReadsBackThroughTheCoreReader) {
  const tf::PostJob job = job_for("table-table-ac");
  const tf::OrientedPath path = impeller_like_path(25);
  TempDir dir("apt-roundtrip");
  {
    std::ofstream out(dir.path / "p.apt");
    tf::write_apt(out, path, job, tf::PostOptions{});
  }
  const tf::ToolPath back = tf::read_toolpath(dir.path / "p.apt", job.tool);
  ASSERT_EQ(back.rows.size(), path.rows.size());  // the RAPID approach and retract are not cutting rows
  for (size_t i = 0; i < path.rows.size(); ++i) {
    EXPECT_LT((back.rows[i].p - path.rows[i].p).norm(), 1e-3) << i;
    EXPECT_LT(angle_deg(back.rows[i].n, path.rows[i].axis), 1e-4) << i;
    EXPECT_NEAR(back.rows[i].feed, 1500.0, 1e-9);
  }
}

TEST(Post, BundledMachinesLoad) {
  for (const char* name : {"xyz", "table-table-ac", "table-table-bc", "head-table-bc", "head-head-ac"})
    EXPECT_NO_THROW(tf::read_machine_json(machine_file(name))) << name;
}

}  // namespace
