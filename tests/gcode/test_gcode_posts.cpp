// What CAM posts commonly write (program numbers, safety lines, coolant, optional stops, dwells, full-turn
// helices, "%" delimiters) and what stays an error: exponents, parameters, expressions, O-word
// subroutines and subprogram calls, each naming its line.
#include <gtest/gtest.h>

#include <cmath>

#include "gcode_test_util.hpp"

namespace tf {
namespace {

using test::expect_gcode_error;
using test::parse_program;

TEST(GcodePosts, AFanucStyleHeaderAndFooterReadWithoutWarnings) {
  const Program p = parse_program(
      "%\nO1234 (PART 7)\nN5 G17 G40 G49 G80 G90 G94 G21\nN10 G91 G28 Z0.\nN15 G90\nN20 T1 M06\n"
      "N25 G00 G54 X10. Y20. S3000 M03\nN30 G43 H1 Z50. M08\nN35 G04 P1.5\nN40 G01 Z-1. F200.\nM01\n"
      "N45 G00 Z50. M09\nN50 G91 G28 Z0.\nN55 G28 X0. Y0.\nN60 M30\n%\nG0 X999\n");
  // Nothing after the closing %; the G28s move nothing before going home, and the last G91 G28 Z0 goes up
  // to the reference height (the program's highest Z, 50: where it is already).
  ASSERT_EQ(p.blocks.size(), 5u);
  EXPECT_DOUBLE_EQ(p.blocks[4].target.z, p.blocks[3].target.z);
  EXPECT_DOUBLE_EQ(p.blocks[2].dwell_s, 1.5);  // G4 P1.5: the feed block waits first
  EXPECT_DOUBLE_EQ(p.blocks[1].dwell_s, 0.0);
  EXPECT_EQ(p.blocks[0].tool, 1);
  for (const std::string& w : p.warnings)
    EXPECT_TRUE(w.find("G28") != std::string::npos || w.find("G54") != std::string::npos) << w;
}

// G2/G3 P n: n - 1 full turns first, the helix's travel shared by angle.
TEST(GcodePosts, ArcTurnsBecomeFullCircles) {
  const Program p = parse_program("G0 X10 Y0 Z0\nG3 X-10 Y0 Z-5 I-10 J0 P3 F100\n");
  ASSERT_EQ(p.blocks.size(), 4u);
  // Total angle 2 x 360 + 180 = 900 deg: each full turn takes 360 / 900 of the 5 mm.
  EXPECT_NEAR(p.blocks[1].target.x, 10, 1e-12);
  EXPECT_NEAR(p.blocks[1].target.z, -2, 1e-12);
  EXPECT_NEAR(p.blocks[2].target.z, -4, 1e-12);
  EXPECT_NEAR(p.blocks[3].target.x, -10, 1e-12);
  EXPECT_NEAR(p.blocks[3].target.z, -5, 1e-12);
  for (int i = 1; i < 4; ++i) EXPECT_LT(p.blocks[size_t(i)].arc_center.head<2>().norm(), 1e-12);
  expect_gcode_error("G0 X10 Y0 Z0\nG3 X-10 Y0 I-10 J0 P1.5 F100\n", 2, "P1.5");
}

TEST(GcodePosts, NumbersAsRs274WritesThem) {
  const Program p = parse_program("G0 X+1. Y-.5 Z0\nG1 X.25 F100.\n");
  ASSERT_EQ(p.blocks.size(), 2u);
  EXPECT_DOUBLE_EQ(p.blocks[0].target.y, -0.5);
  EXPECT_DOUBLE_EQ(p.blocks[1].target.x, 0.25);
  expect_gcode_error("G0 X0 Y0 Z0\nG1 X1e3 F100\n", 2, "X1E3");   // the E is a word, as LinuxCNC reads it
  expect_gcode_error("G0 X0 Y0 Z0\nG1 X1E-3 F100\n", 2, "X1E-3");
  expect_gcode_error("G0 X0 Y0 Z0\nG1 X1.5e2 F100\n", 2, "X1.5E2");
}

}  // namespace
}  // namespace tf
