// RS274/NGC rules the reader follows as LinuxCNC does (each case checked against LinuxCNC's rs274): full
// circles without axis words, axes a block needs before the program set them, inverse-time arcs of
// several turns, G94 clearing the feed, the arc-centre tolerance, one code per modal group, "%" lines,
// words nothing uses, splines.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <numbers>

#include "gcode_test_util.hpp"

namespace tf {
namespace {

using test::expect_gcode_error;
using test::parse_program;

TEST(GcodeLinuxcncRules, FullCircleWithoutAxisWords) {
  const Program p = parse_program("G21 G90\nG0 X0 Y10 Z5\nG2 F100 I5\nG3 I-5 P2\n");
  ASSERT_EQ(p.blocks.size(), 4u);
  EXPECT_EQ(p.blocks[1].motion, Motion::ArcCW);
  EXPECT_DOUBLE_EQ(p.blocks[1].target.x, 0.0);
  EXPECT_DOUBLE_EQ(p.blocks[1].target.y, 10.0);
  EXPECT_DOUBLE_EQ(p.blocks[1].arc_center.x(), 5.0);
  EXPECT_EQ(p.blocks[2].motion, Motion::ArcCCW);  // two full turns, one block each
  EXPECT_EQ(p.blocks[3].motion, Motion::ArcCCW);
  EXPECT_DOUBLE_EQ(p.blocks[3].arc_center.x(), -5.0);
}

TEST(GcodeLinuxcncRules, IncrementalWordsOnAnUnsetAxisStartAtZero) {
  // LinuxCNC cuts a 10 mm square from X0 Y0.
  const Program p = parse_program("G21 G91\nG1 F100 Z-2\nX10\nY10\nX-10\nY-10\n");
  ASSERT_EQ(p.blocks.size(), 5u);
  const double want[5][2] = {{0, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 0}};
  for (int k = 0; k < 5; ++k) {
    EXPECT_DOUBLE_EQ(p.blocks[size_t(k)].target.x, want[k][0]) << k;
    EXPECT_DOUBLE_EQ(p.blocks[size_t(k)].target.y, want[k][1]) << k;
    EXPECT_DOUBLE_EQ(p.blocks[size_t(k)].target.z, -2.0) << k;
  }
}

TEST(GcodeLinuxcncRules, AnArcFromAnUnsetAxisStartsAtZero) {
  // A half circle from X0 (where LinuxCNC starts) to X10 about X5, not a full one.
  const Program p = parse_program("G21 G90\nG0 Y0 Z5\nG2 F100 X10 Y0 I5 J0\n");
  ASSERT_EQ(p.blocks.size(), 2u);
  EXPECT_DOUBLE_EQ(p.blocks[0].target.x, 0.0);
  EXPECT_DOUBLE_EQ(p.blocks[1].target.x, 10.0);
  EXPECT_DOUBLE_EQ(p.blocks[1].arc_center.x(), 5.0);
  // Absolute axis words still place an unset axis where the program first puts it.
  const Program q = parse_program("G21 G90\nG0 Y0 Z5\nG1 F100 X7\n");
  EXPECT_DOUBLE_EQ(q.blocks[0].target.x, 7.0);
}

TEST(GcodeLinuxcncRules, InverseTimeArcOfSeveralTurnsTakesOneF) {
  // G93: F1 is one minute for the whole arc, whatever its turns: the blocks' minutes (1 / F) add up to 1.
  const Program p = parse_program("G21 G90 G17\nG0 X0 Y0 Z0\nG93 G2 X10 Y0 I5 J0 P3 F1\n");
  ASSERT_EQ(p.blocks.size(), 4u);
  double minutes = 0.0;
  for (size_t k = 1; k < p.blocks.size(); ++k) minutes += 1.0 / p.blocks[k].feed;
  EXPECT_NEAR(minutes, 1.0, 1e-12);
  EXPECT_NEAR(p.blocks[1].feed, 2.5, 1e-12);  // a full turn: 2 pi of the 5 pi
  EXPECT_NEAR(p.blocks[3].feed, 5.0, 1e-12);  // the last half turn
}

TEST(GcodeLinuxcncRules, G94ClearsTheFeed) {
  // LinuxCNC: "Cannot do g1 with zero feed rate".
  expect_gcode_error("G21\nG0 X0 Y0 Z0\nG93 G1 X5 F2\nG94 G1 X10\n", 4, "F");
  expect_gcode_error("G21\nG0 X0 Y0 Z0\nG1 X5 F100\nG94\nG1 X10\n", 5, "F");
  EXPECT_EQ(parse_program("G21\nG0 X0 Y0 Z0\nG1 X5 F100\nG94 G1 X10 F200\n").blocks.back().feed, 200.0);
}

TEST(GcodeLinuxcncRules, ArcCentreToleranceIsLinuxcncs) {
  // A quarter circle written to two decimals (radii 1 and 1.0041): LinuxCNC runs it.
  EXPECT_EQ(parse_program("G21\nG0 X3 Y3 Z0\nG3 F100 X2.71 Y3.71 I-1 J0\n").blocks.size(), 2u);
  EXPECT_EQ(parse_program("G21\nG0 X0 Y0 Z0\nG2 F100 X2.027 Y0 I1 J0\n").blocks.size(), 2u);
  // 0.029 mm and 2.8 %: refused, as by LinuxCNC; 0.1 mm on a 100 mm radius (0.1 %) is not.
  expect_gcode_error("G21\nG0 X0 Y0 Z0\nG2 F100 X2.029 Y0 I1 J0\n", 3, "I");
  EXPECT_EQ(parse_program("G21\nG0 X0 Y0 Z0\nG2 F100 X200.1 Y0 I100 J0\n").blocks.size(), 2u);
  expect_gcode_error("G21\nG0 X0 Y0 Z0\nG2 F100 X200.2 Y0 I100 J0\n", 3, "I");
}

TEST(GcodeLinuxcncRules, OneCodePerModalGroup) {
  expect_gcode_error("G90 G91 G0 X1 Y1 Z1\n", 1, "G91");
  expect_gcode_error("G0 X1 Y1 Z1\nG17 G18\n", 2, "G18");
  expect_gcode_error("G20 G21\n", 1, "G21");
  expect_gcode_error("M3 M4 S1000\n", 1, "M4");
  EXPECT_EQ(parse_program("G17 G21 G90 G94 G40 G49 G54 G64 G80\nG0 X1 Y1 Z1\n").blocks.size(), 1u);
  // G80 may share a block with another motion code, which then is the block's motion (LinuxCNC's
  // read_g); two others may not.
  const Program p = parse_program("G21\nG0 X0 Y0 Z10\nG0 G80 Z30\nG80 G1 X5 F100\n");
  ASSERT_EQ(p.blocks.size(), 3u);
  EXPECT_EQ(p.blocks[1].motion, Motion::Rapid);
  EXPECT_EQ(p.blocks[2].motion, Motion::Linear);
  EXPECT_DOUBLE_EQ(p.blocks[2].target.x, 5.0);
  expect_gcode_error("G21\nG0 G1 G80 X1 F100\n", 2, "G1");
}

// A "%" line opens a program only before any other line but blank ones, and then the next one ends it;
// anywhere else rs274 refuses it ("Bad character '%' used"; a stray one was read as an opening before).
TEST(GcodeLinuxcncRules, PercentOnlyOpensAndEndsAProgram) {
  expect_gcode_error("G21 G90\nG0 X1\n%\nG0 X2\nM2\n", 3, "%");
  expect_gcode_error("(title)\n%\nG0 X1\n%\n", 2, "%");
  EXPECT_EQ(parse_program("\n  %\nG21\nG0 X1 Y1 Z1\n%\nG0 X2\n").blocks.size(), 1u);
  EXPECT_EQ(parse_program("G21\nG0 X1 Y1 Z1\nM2\n%\n").blocks.size(), 1u);
}

// Words nothing in the block uses, and an arc's offset across its plane: LinuxCNC refuses them (found in
// review: "G1 X5 R3", probably meant as an arc, ran as a line).
TEST(GcodeLinuxcncRules, WordsNothingUsesAreRefused) {
  expect_gcode_error("G21\nG0 X0 Y0 Z0\nG1 F100 X5 R3\n", 3, "R3");
  expect_gcode_error("G21\nG0 X0 Y0 Z0\nG1 F100 X5 I3\n", 3, "I3");
  expect_gcode_error("G21\nG0 X0 Y0 Z0\nG2 F100 X10 Y0 I5 J0\nI3\n", 4, "I3");
  expect_gcode_error("G21 G17\nG0 X0 Y0 Z0\nG2 F100 X10 Y0 I5 K3\n", 3, "K3");
  expect_gcode_error("G21 G90.1\nG0 X0 Y0 Z0\nG2 F100 X10 Y10 I5\n", 3, "J");
  expect_gcode_error("G21\nS-100 M3\n", 2, "S-100");
  // A line number only begins a line: rs274 stops at "G1 N5 X10" ("Bad character 'n' used").
  expect_gcode_error("G21\nG0 X0 Y0 Z0\nG1 N5 X10 F100\n", 3, "N5");
  expect_gcode_error("G21\nN4 N5 G0 X1\n", 2, "N5");
  EXPECT_EQ(parse_program("G21\nN4 G0 X0 Y0 Z0\n/N5 G1 X10 F100\n").blocks.size(), 2u);
  // What uses them: arcs (modal too), helices, the other planes, cycles' R.
  EXPECT_EQ(parse_program("G21\nG0 X0 Y0 Z0\nG2 F100 X10 Y0 Z-1 I5 J0\nX0 Y0 I-5 J0\nG18 G2 X10 Z-1 I5 K0\n"
                          "G19 G3 Y10 Z-1 J5 K0\nG17 G3 X0 Y0 R12\nG90.1 G2 X10 Y0 I5 J0\n")
                .blocks.size(),
            7u);
  EXPECT_EQ(parse_program("G21\nG0 X0 Y0 Z10\nG81 X5 Y5 Z-2 R2 F100\nG80\n").blocks.size(), 5u);  // G0, the drill's 4
}

// A program LinuxCNC's rs274 refuses, the line it stops at and the word or code named.
// P, Q, L, H and D with nothing in the block to use them, as LinuxCNC's rs274 refuses each ("P word with
// no G2 G3 G4 ... to use it"); and each with a code that uses it, which it accepts.
TEST(GcodeLinuxcncRules, ParameterWordsNeedACodeThatUsesThem) {
  expect_refused({
      {"G21\nG0 X0 Y0 Z0\nG1 F100 X5 P2\n", 3, "P2"},
      {"G21\nG0 X0 Y0 Z0\nG1 F100 X5\nX6 P2\n", 4, "P2"},  // modal G1
      {"G21\nM3 S1000 P1\n", 2, "P1"},
      {"G21\nG0 X0 Y0 Z5\nG81 X1 Y1 Z-1 R1 P1 F100\n", 3, "P1"},  // G81 has no dwell
      {"G21\nG4 P1 Q1\n", 2, "Q1"},
      {"G21\nG0 X0 Y0 Z5\nG81 X1 Y1 Z-1 R1 Q1 F100\n", 3, "Q1"},  // nor a peck
      {"G21\nG0 X0 Y0 Z5\nG81 X1 Y1 Z-5 R2 I1 F100\n", 3, "I1"},
      {"G21\nM6 T1 Q1\n", 2, "Q1"},
      {"G21\nG0 X0 Y0 Z0\nG2 F100 X2 I1 L1\n", 3, "L1"},
      {"G21\nG0 X0 Y0 Z5\nM4 S100\nG74 X1 Y1 Z-5 R2 L2 F100\n", 4, "L2"},  // G74 takes no repeats
      {"G21\nG42.1 D2 L1\n", 2, "L1"},                                       // L only in G18
      {"G21\nM6 T1 H1\n", 2, "H1"},
      {"G21\nG49 H1\n", 2, "H1"},
      {"G21\nG40 D1\n", 2, "D1"},
      {"G21\nG0 X0 Y0 Z0 R1\n", 2, "R1"},
      {"G21\nM70 P1\n", 2, "P1"},
      {"G21\nM19 R90 P3\n", 2, "P3"},
  });
  GcodeOptions tools;
  tools.tool_lengths[1] = 50.0;
  const Program p = parse_program(
      "G21 G90\nT1 M6\nG43 H1\nG64 P0.01 Q0.01\nM61 Q1\nM19 R10 Q1\nG4 P0.5\nG0 X0 Y0 Z5\n"
      "G2 F100 X0 Y0 I5 P2\nM3 S1000\nG82 X1 Y1 Z-1 R1 P0.5\nG83 X2 Y1 Z-1 R1 Q0.5\nG81 X3 Y1 Z-1 R1 L2\n"
      "G84 X4 Y1 Z-1 R1 P0.2\nG80\nG10 L2 P1 X0\nG41 D1\nG40\nM62 P1\nM66 P0 L0 Q1\nM100 P1 Q2\n",
      tools);
  EXPECT_GT(p.blocks.size(), 10u);
}

// Codes the reader accepts without effect or with a warning (cutter compensation's rules are kept, and
// a move under it with an offset is refused: the compensated path is not simulated), and those it
// refuses as rs274 does.
TEST(GcodeLinuxcncRules, CodesWithoutEffectKeepTheirRules) {
  EXPECT_EQ(parse_program("G21\nG0 X0 Y0 Z5\nG97 S500 G0 X1\nG96 D2000 S100 G1 X2 F100\nG41.1 D2 R1\nG40\n"
                          "G18 G42.1 D2 L1\nG40\nG17 G41 D1 L1\nG40\nG8 G1 X3\nM19 R90 P1\n")
                .blocks.size(),
            4u);
  // D0 offsets nothing: the programmed path is the tool's.
  EXPECT_EQ(parse_program("G21\nG0 X0 Y0 Z5\nG41 D0\nG1 X10 F100\nG40\nG42.1 D0\nG0 Y3\n").blocks.size(), 3u);
  expect_refused({
      {"G21\nG18\nG41 D1\nG17\n", 4, "G17"},  // a plane change with compensation on
      {"G21\nG41 D1\nG42 D1\n", 3, "G42"},     // on when on
      {"G21\nG19 G41 D1\n", 2, "G41"},          // not in G19
      {"G21\nG41 G41.1 D1\n", 2, "G41.1"},      // one modal group
      // A move under compensation with an offset: the tool's radius, the spindle's tool, a diameter.
      {"G21\nG0 X0 Y0 Z5\nG41 D1\nG1 X10 F100\n", 4, "G41 D1"},
      {"G21\nG0 X0 Y0 Z5\nG42\nG0 X10\n", 4, "G42"},
      {"G21\nG0 X0 Y0 Z5\nG42.1 D6 G1 X10 F100\n", 3, "G42.1 D6"},
      {"G21\nG0 X0 Y0 Z5\nG41.1 D2\nG81 X1 Y1 Z-1 R1 F100\n", 4, "G41.1 D2"},
      {"G21\nG96 D2000\n", 2, "G96"},           // without its S
      {"G21\nG7\n", 2, "G7"},
      {"G21\nG17.1\n", 2, "G17.1"},
      {"G21\nG16\nG0 X10 Y45\n", 2, "G16"},  // polar: X10 Y45 is not a point
      // Unknown codes with axis words, which would run in the motion mode in force.
      {"G21\nG0 X0 Y0 Z5\nG15 X1\n", 3, "G15"},  // not an RS274/NGC code
      {"G21\nG0 X0 Y0 Z5\nG1 F100 X1\nG84.2 X1 Y2 Z3 Q5 R1\n", 4, "G84.2"},  // not a drilling cycle
  });
  // An M code the reader does not know (a remapped one) is ignored with a warning, its P and Q with it.
  const Program remapped = parse_program("G21\nM400 P10 Q43\nG0 X0 Y0 Z5\n");
  EXPECT_EQ(remapped.blocks.size(), 1u);
  ASSERT_FALSE(remapped.warnings.empty());
  EXPECT_NE(remapped.warnings.front().find("M400"), std::string::npos);
}

// G5 and G5.1 as LinuxCNC reads them (its interpreter's convert_spline and rs274's answers): XY only, no
// Z or rotary motion, I and J together (G5: or neither, continuing the previous G5), G5 with P and Q, an
// end; NURBS are refused. Stricter than rs274: a spline under G93, whose F LinuxCNC does not apply.
TEST(GcodeLinuxcncRules, SplinesKeepTheirRules) {
  expect_refused({
      {"G21\nG0 X0 Y0 Z0\nG5.2 X1 Y1 P1\n", 3, "G5.2"},
      {"G21 F100\nG0 X0 Y0 Z0\nG18\nG5.1 X5 Z5 I2 J0\n", 4, "G5.1"},
      {"G21 F100\nG0 X0 Y0 Z0\nG5 I1 J1 P-1 Q1 X20 Y0 Z3\n", 3, "Z3"},
      {"G21 F100\nG0 X0 Y0 Z0\nG5.1 X5 Y5 I2\n", 3, "I2"},
      {"G21 F100\nG0 X0 Y0 Z0\nG5 I1 J1 X5 Y5\n", 3, "G5"},        // P and Q
      {"G21 F100\nG0 X0 Y0 Z0\nG93\nG5.1 X5 Y5 I1 J1 F2\n", 4, "G5.1"},  // G93
      {"G21\nG0 X0 Y0 Z0\nG5 I0 J3 P0 Q-3 X1 Y1\n", 3, "F"},       // no feed
      {"G21 F100\nG0 X0 Y0 Z0\nG5.1 I1 J1\n", 3, "G5.1"},          // no end
      {"G21 F100\nG0 X0 Y0 Z0\nG41 D1\nG5.1 X5 Y5 I2 J0\n", 4, "G5.1"},  // cutter compensation
      {"G21 F100\nG0 X0 Y0 Z0\nG5.1 X5 Y5 I2 J0 K1\n", 3, "K1"},
  });
}

// G5.1 from (0, 0) over the control point (5, 10) to (10, 0) is the parabola y = 2x - x^2/5: every chord
// ends on it and stands off it by at most 0.0005 mm. The motion mode stays G1.
TEST(GcodeLinuxcncRules, QuadraticSplineFollowsItsParabola) {
  const Program p = parse_program("G21 G90 G17\nG0 X0 Y0 Z0\nG1 F100 Z-1\nG5.1 X10 Y0 I5 J10\nX12\nM2\n");
  ASSERT_GT(p.blocks.size(), 20u);
  auto parabola = [](double x) { return 2.0 * x - x * x / 5.0; };
  double x0 = 0.0, y0 = 0.0, worst = 0.0;
  for (size_t k = 2; k + 1 < p.blocks.size(); ++k) {
    const Block& b = p.blocks[k];
    EXPECT_EQ(b.motion, Motion::Linear);
    EXPECT_EQ(b.line, 4);
    EXPECT_NEAR(b.target.y, parabola(b.target.x), 1e-9);
    EXPECT_DOUBLE_EQ(b.target.z, -1.0);
    for (double f = 0.05; f < 1.0; f += 0.05) {  // the chord against the curve between its ends
      const double x = x0 + f * (b.target.x - x0), y = y0 + f * (b.target.y - y0);
      worst = std::max(worst, std::abs(y - parabola(x)) / std::sqrt(1.0 + std::pow(2.0 - 2.0 * x / 5.0, 2)));
    }
    x0 = b.target.x, y0 = b.target.y;
  }
  EXPECT_LE(worst, 5e-4);
  EXPECT_DOUBLE_EQ(p.blocks[p.blocks.size() - 2].target.x, 10.0);
  EXPECT_EQ(p.blocks.back().motion, Motion::Linear);  // "X12": still G1
  EXPECT_DOUBLE_EQ(p.blocks.back().target.x, 12.0);
}

// G5's curve, independently: B(1/2) = (P0 + 3 P1 + 3 P2 + P3) / 8 lies on the chords (within 0.0005 mm),
// in inches and in G91 (I J P Q are offsets either way). Without I J, G5 mirrors the previous G5's P Q
// (LinuxCNC's cycle_i, cycle_j: 0 before any G5), so consecutive G5s join without a kink.
TEST(GcodeLinuxcncRules, CubicSplineMidpointAndSmoothContinuation) {
  auto distance_to_chords = [](const Program& p, int line, Eigen::Vector2d q, Eigen::Vector2d from) {
    double best = 1e9;
    for (const Block& b : p.blocks) {
      if (b.line != line) continue;
      const Eigen::Vector2d to(b.target.x, b.target.y), d = to - from;
      const double t = std::clamp((q - from).dot(d) / std::max(d.squaredNorm(), 1e-30), 0.0, 1.0);
      best = std::min(best, (from + t * d - q).norm());
      from = to;
    }
    return best;
  };
  // G20 G91 from (1, 1) inch: P0 (1, 1), P1 P0 + (1, 2), P3 P0 + (4, 0), P2 P3 + (-1, 2).
  const Program p = parse_program("G20 G90 G17\nG0 X1 Y1 Z0\nG91 G1 F10\nG5 I1 J2 P-1 Q2 X4 Y0\nG5 P-1 Q-2 X4 Y0\nM2\n");
  const double in = 25.4;
  const Eigen::Vector2d p0(in, in), p1 = p0 + in * Eigen::Vector2d(1, 2), p3 = p0 + in * Eigen::Vector2d(4, 0),
                        p2 = p3 + in * Eigen::Vector2d(-1, 2);
  EXPECT_LE(distance_to_chords(p, 4, (p0 + 3 * p1 + 3 * p2 + p3) / 8.0, p0), 5e-4);
  // The second: from P3 through P3 + (1, -2) (the mirror) and end + (-1, -2) to P3 + (4, 0).
  const Eigen::Vector2d q1 = p3 + in * Eigen::Vector2d(1, -2), q3 = p3 + in * Eigen::Vector2d(4, 0),
                        q2 = q3 + in * Eigen::Vector2d(-1, -2);
  EXPECT_LE(distance_to_chords(p, 5, (p3 + 3 * q1 + 3 * q2 + q3) / 8.0, p3), 5e-4);
  EXPECT_NEAR(p.blocks.back().target.x, 9 * in, 1e-9);
  EXPECT_NEAR(p.blocks.back().target.y, in, 1e-9);
  // The joint: the last chord of the first and the first chord of the second point the same way.
  const Block* last_first = nullptr;
  const Block* first_second = nullptr;
  for (size_t k = 0; k < p.blocks.size(); ++k) {
    if (p.blocks[k].line == 4) last_first = &p.blocks[k];
    if (p.blocks[k].line == 5 && !first_second) first_second = &p.blocks[k];
  }
  ASSERT_TRUE(last_first && first_second);
  const Block& before = *(last_first - 1);
  const Eigen::Vector2d a(last_first->target.x - before.target.x, last_first->target.y - before.target.y);
  const Eigen::Vector2d b(first_second->target.x - last_first->target.x, first_second->target.y - last_first->target.y);
  EXPECT_GT(a.normalized().dot(b.normalized()), std::cos(0.1));
  // A first G5 without I J starts along its start (P1 = P0): accepted, as by rs274.
  EXPECT_GT(parse_program("G21 F100\nG0 X0 Y0 Z0\nG5 P-1 Q1 X15 Y0\n").blocks.size(), 2u);
}

}  // namespace
}  // namespace tf

namespace tf {
namespace {

// Polar coordinates and the spindle-synchronised moves keep LinuxCNC's rules (its enhance_block and
// check_other_codes); where they go is judged by rs274 in test_rs274_judge.cpp.
TEST(GcodeLinuxcncRules, PolarAndSynchronisedMovesKeepTheirRules) {
  expect_refused({
      {"G21\nG18\nG0 @5 ^10\n", 3, "@5"},               // G17 only (the plane before the block, as LinuxCNC)
      {"G21\nG18\nG17 G0 @5 ^10\n", 3, "@5"},
      {"G21\nG0 X1 Y0 Z0\nG91 G0 @-1 ^10\n", 3, "^10"},  // at the origin after the distance
      {"G21\nM3 S100\nG33.1 Z-3 K1\n", 3, "G33.1"},       // a tap from a Z not set yet: it returns there
      {"G21\nG0 X1 @5 ^10\n", 2, "X1"},                  // not with X or Y
      {"G21\nG53 G0 @5 ^10\n", 2, "@5"},                 // not with G53
      {"G21\nG92 @5 ^10\n", 2, "@5"},                    // motion only
      {"G21\nG0 X0 Y0 Z0\nG91 G0 ^10\n", 3, "^10"},      // incremental from the origin: no direction
      {"G21\nG0 X0 Y0 Z0\nG0 @5\n", 3, "@5"},            // a distance without an angle at the origin
      {"G21\nG0 X0 Y0 Z0\nG80 @5\n", 3, "G80"},          // no motion mode
      {"G21\nM3 S100\nG33 Z-5\n", 3, "G33"},            // K missing
      {"G21\nM3 S100\nG33 Z-5 K1 F100\n", 3, "F100"},   // F with G33
      {"G21\nS100\nG33 Z-5 K1\n", 3, "G33"},            // spindle stopped
      {"G21\nG0 Z0\nM3 S100\nG33.1 Z-5 K-1\n", 4, "K-1"},  // K must be positive
      {"G21\nM3 S100\nG33 Z-5 K1 I2\n", 3, "I2"},       // I only with G33.1
      {"G21\nM3 S100\nG76 P1 Z-5 I-1 J1 K1 E0.5\n", 3, "G76"},  // a lathe cycle, not an exponent
      {"G21\nG0 X0 Y0 Z0\nG71.1 Q100 X1 Z1 D1\n", 3, "G71.1"},  // lathe roughing
  });
  // G33 feeds K per turn at the spindle's speed; G33.1 goes in at that feed and out I times as fast, back
  // to where it started.
  const Program p = parse_program("G20 G90\nG0 X1 Y2 Z0.5\nM3 S600\nG33 Z-0.5 K0.05\nG0 Z0.5\nG33.1 Z-0.25 K0.1 I2\n");
  ASSERT_EQ(p.blocks.size(), 5u);
  EXPECT_EQ(p.blocks[1].motion, Motion::Linear);
  EXPECT_NEAR(p.blocks[1].feed, 0.05 * 25.4 * 600, 1e-9);
  EXPECT_NEAR(p.blocks[3].target.z, -0.25 * 25.4, 1e-9);
  EXPECT_NEAR(p.blocks[3].feed, 0.1 * 25.4 * 600, 1e-9);
  EXPECT_NEAR(p.blocks[4].target.z, 0.5 * 25.4, 1e-9);
  EXPECT_NEAR(p.blocks[4].feed, 2 * 0.1 * 25.4 * 600, 1e-9);
  EXPECT_EQ(p.blocks[4].feed_mode, FeedMode::PerMinute);
}

}  // namespace
}  // namespace tf
