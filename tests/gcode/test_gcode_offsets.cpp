// Work offsets, the tool library and tool length offsets, reference returns: what the reader does that
// rs274 cannot judge (the scene's side: warnings, errors, tool tips under TCP, G28's unknown home).
#include <gtest/gtest.h>

#include <cmath>

#include "gcode_test_util.hpp"
#include "tiltfield/core/kinematics.hpp"

namespace tf {
namespace {

GcodeOptions two_tools() {
  GcodeOptions o;
  o.tool_lengths = {{1, 50.0}, {2, 80.0}};
  o.tool_length = 50.0;
  o.start_tool = 1;
  o.work_offsets = {{"G54", {100, 50, -20, 0, 0, 0}}};
  return o;
}

using test::expect_gcode_error;
using test::parse_program;

bool has_offset_warning(const Program& p, const std::string& text) {
  for (const std::string& w : p.warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

TEST(GcodeOffsets, G54IsInForceFromTheStartAndAnUndefinedOffsetIsZeroWithAWarning) {
  const Program p = parse_program("G0 X1 Y2 Z3\nG55 G0 X1 Y2 Z3\nG54 G0 X0\n", two_tools());
  ASSERT_EQ(p.blocks.size(), 3u);
  EXPECT_DOUBLE_EQ(p.blocks[0].target.x, 101);
  EXPECT_DOUBLE_EQ(p.blocks[0].target.z, -17);
  EXPECT_DOUBLE_EQ(p.blocks[1].target.x, 1);  // G55 is not in the scene: zero
  EXPECT_DOUBLE_EQ(p.blocks[2].target.x, 100);
  EXPECT_DOUBLE_EQ(p.blocks[2].target.y, 2);  // selecting G54 moves nothing: Y stays where it is
  EXPECT_TRUE(has_offset_warning(p, "p.ngc:2: G55 is not in the scene's work_offsets")) << p.warnings.front();
  EXPECT_FALSE(has_offset_warning(p, "G54"));
}

// 3-axis with tool length offsets: X Y Z (plus offsets) move the spindle nose; the tip is the loaded
// tool's gauge length below. With the right H the tip is where the program says; H of another tool puts
// it off by the difference; without an offset (G49) the nose is at the programmed point.
TEST(GcodeOffsets, ToolLengthOffsetsOnAThreeAxisMachine) {
  const Program p = parse_program("T1 M6\nG43 H1\nG0 X0 Y0 Z10\nT2 M6\nG43 H2 Z10\nG43 H1 Z10\nG49 Z10\nM30\n", two_tools());
  ASSERT_EQ(p.blocks.size(), 4u);
  EXPECT_EQ(p.blocks[0].tool, 1);
  EXPECT_EQ(p.blocks[1].tool, 2);
  EXPECT_DOUBLE_EQ(p.blocks[0].target.z, -10);        // 10 + G54's -20
  EXPECT_DOUBLE_EQ(p.blocks[1].target.z, -10);        // tool 2 with its own H
  EXPECT_DOUBLE_EQ(p.blocks[2].target.z, -10 - 30);   // tool 2 with tool 1's 30 mm shorter offset
  EXPECT_DOUBLE_EQ(p.blocks[3].target.z, -10 - 80);   // no offset: the nose at -10
}

// A program without G43 keeps the reading of a touched-off tool: X Y Z are the tip, whatever the tool.
TEST(GcodeOffsets, WithoutG43TheTipIsTheProgrammedPoint) {
  const Program p = parse_program("T2 M6\nG0 X0 Y0 Z10\n", two_tools());
  ASSERT_EQ(p.blocks.size(), 1u);
  EXPECT_DOUBLE_EQ(p.blocks[0].target.z, -10);
}

// Under TCP the controller tracks the point the offset names: with the loaded tool's own offset the tip
// is the programmed point; with another's it is off along the tool axis by the difference.
TEST(GcodeOffsets, TcpTipsFollowTheToolAxis) {
  MachineSpec m;
  m.kinematics = KinematicsType::TableTableAC;
  GcodeOptions o = two_tools();
  o.work_offsets.clear();
  const Program p = parse_program("T1 M6\nG0 X0 Y0 Z50 A0 C0\nG43.4 H1\nG1 X1 Y2 Z3 A30 C40 F100\nG43.4 H2\nG1 X1 Y2 Z3\n", o, m);
  ASSERT_EQ(p.blocks.size(), 3u);
  EXPECT_TRUE(p.blocks[1].tcp);
  EXPECT_NEAR(p.blocks[1].target.x, 1, 1e-12);
  EXPECT_NEAR(p.blocks[1].target.z, 3, 1e-12);
  const Eigen::Vector3d axis = Kinematics(m, 0.0).forward(Joints{0, 0, 0, 30, 0, 40}).axis;
  const Eigen::Vector3d tip(p.blocks[2].target.x, p.blocks[2].target.y, p.blocks[2].target.z);
  EXPECT_LT((tip - (Eigen::Vector3d(1, 2, 3) + 30.0 * axis)).norm(), 1e-9) << tip.transpose();
}

TEST(GcodeOffsets, G49EndsG43Point4ButNotAnMCodesTcp) {
  MachineSpec m;
  m.kinematics = KinematicsType::TableTableAC;
  m.tcp_on_code = "M428";
  m.tcp_off_code = "M429";
  const Program p = parse_program("M428\nG0 X0 Y0 Z5 A0 C0\nG49 G0 Z6\nM429\nG0 Z7\nG43.4\nG0 Z8\nG49\nG0 Z9\n", GcodeOptions{}, m);
  ASSERT_EQ(p.blocks.size(), 5u);
  EXPECT_TRUE(p.blocks[0].tcp);
  EXPECT_TRUE(p.blocks[1].tcp);
  EXPECT_FALSE(p.blocks[2].tcp);
  EXPECT_TRUE(p.blocks[3].tcp);
  EXPECT_FALSE(p.blocks[4].tcp);
}

TEST(GcodeOffsets, ToolsTheLibraryLacksAreErrorsWhereTheyMove) {
  const GcodeOptions o = two_tools();
  expect_gcode_error("T5 M6\nG0 X0 Y0 Z10\n", 2, "T5", o);
  expect_gcode_error("T0 M6\nG0 X0 Y0 Z10\n", 2, "T0", o);
  expect_gcode_error("T1 M6\nG43 H9\n", 2, "H9", o);
  expect_gcode_error("T1 M6\nG43.1 Z2\n", 2, "G43.1", o);
  // Unloading at the end is fine, and a scene without a library answers every number.
  EXPECT_EQ(parse_program("T1 M6\nG0 X0 Y0 Z10\nT0 M6\nM30\n", o).blocks.size(), 1u);
  EXPECT_EQ(parse_program("T5 M6\nG43 H5\nG0 X0 Y0 Z10\n", GcodeOptions{}).blocks.front().tool, 5);
}

// G28: the rapid to the intermediate point is simulated, then Z straight up to the reference height (the
// highest Z the program commands: a traverse after "G91 G28 Z0" must not run at the next cutting depth,
// found in review); the other axes sent home take the value the program next gives them, and blocks that
// move while one of them stays home are dropped with a warning.
TEST(GcodeOffsets, ReferenceReturns) {
  const Program p = parse_program("G0 X10 Y10 Z5\nG91 G28 Z20\nG90 G0 X50 Y50\nG0 Z8\nG28 X0 Y0\nG0 X1\nM30\n", GcodeOptions{});
  ASSERT_EQ(p.blocks.size(), 6u);
  EXPECT_DOUBLE_EQ(p.blocks[1].target.z, 25);  // intermediate point, incremental
  EXPECT_DOUBLE_EQ(p.blocks[2].target.z, 25);  // Z home: the highest Z of the program, X Y unchanged
  EXPECT_DOUBLE_EQ(p.blocks[2].target.x, 10);
  EXPECT_DOUBLE_EQ(p.blocks[3].target.z, 25);  // the traverse at the reference height
  EXPECT_DOUBLE_EQ(p.blocks[3].target.x, 50);
  EXPECT_DOUBLE_EQ(p.blocks[4].target.z, 8);   // then down where the program puts it
  EXPECT_DOUBLE_EQ(p.blocks[5].target.x, 0);   // G28 X0 Y0's intermediate point
  EXPECT_TRUE(has_offset_warning(p, "G28 reference return"));
  EXPECT_TRUE(has_offset_warning(p, "1 motion blocks after the reference return")) << p.warnings.back();
  // The reviewer's program: the traverse after the tool change height runs above the stock, not at Z5.
  const Program q = parse_program("G0 X-5 Y5 Z15\nG0 Z5\nG1 F100 X5\nG91 G28 Z0\nG90 G0 X15 Y15\nG1 Z5\n", GcodeOptions{});
  ASSERT_EQ(q.blocks.size(), 6u);
  EXPECT_DOUBLE_EQ(q.blocks[3].target.z, 15);  // straight up from (5, 5, 5)
  EXPECT_DOUBLE_EQ(q.blocks[3].target.x, 5);
  EXPECT_DOUBLE_EQ(q.blocks[4].target.z, 15);
}

TEST(GcodeOffsets, G10AndG92NeedTheirWords) {
  const GcodeOptions o;
  expect_gcode_error("G0 X0 Y0 Z0\nG92\n", 2, "G92", o);
  expect_gcode_error("G0 X0 Y0 Z0\nG10 L1 P1 Z5\n", 2, "G10", o);
  expect_gcode_error("G0 X0 Y0 Z0\nG10 L2 X1\n", 2, "G10", o);
  expect_gcode_error("G0 X0 Y0 Z0\nG10 L2 P1 R30\n", 2, "R30", o);
  expect_gcode_error("G0 X0 Y0 Z0\nG91 G53 G0 X1\n", 2, "G53", o);
  expect_gcode_error("G0 X0 Y0 Z0\nG53 G2 X1 I1\n", 2, "G53", o);
  expect_gcode_error("G0 X0 Y0 Z0\nG92 X1 G0 Y2\n", 2, "G92", o);
}

}  // namespace
}  // namespace tf
