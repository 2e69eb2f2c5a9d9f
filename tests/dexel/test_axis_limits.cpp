// The machine's axis limits in the verification: a block's end, an arc's extreme point, and a TCP block
// whose machine X lies beyond its limit while the programmed tip does not (found in review: a program
// with A beyond its limit verified with no word), and a TCP swing beyond a limit between its ends.
#include <gtest/gtest.h>

#include "helpers.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf {
namespace {

Block block(Motion m, const Joints& target, int line) {
  Block b;
  b.motion = m;
  b.target = target;
  b.feed = 1000.0;
  b.line = line;
  return b;
}

VerifyReport verify(const Scene& s, const Program& p) {
  VerifyOptions o;
  o.resolution = 1.0;
  return verify_program(s, p, scene_forward(s), o).report;
}

TEST(AxisLimits, BlockEndsAndArcExtremesBeyondTheLimits) {
  Scene s = test::box_scene({0, 0, 0}, {50, 50, 10}, test::ball_tool(3, 10, 3, 40, {}));
  MachineSpec m;
  m.limits['X'] = {-10, 60};
  m.limits['Y'] = {-10, 60};
  s.machine = m;
  Program p;
  p.start = {45, 5, 50, 0, 0, 0};
  Block ccw = block(Motion::ArcCCW, {45, 45, 50, 0, 0, 0}, 2);  // about (45, 25): passes x = 65
  ccw.arc_center = {45, 25, 50};
  Block back = block(Motion::ArcCCW, {45, 5, 50, 0, 0, 0}, 3);  // on round the other side: x down to 25
  back.arc_center = {45, 25, 50};
  p.blocks = {block(Motion::Rapid, {45, 5, 50, 0, 0, 0}, 1), ccw, back, block(Motion::Rapid, {70, 5, 50, 0, 0, 0}, 4),
              block(Motion::Rapid, {5, 5, 50, 0, 0, 0}, 5)};
  const VerifyReport r = verify(s, p);
  ASSERT_EQ(r.axis_limits.size(), 2u);
  EXPECT_EQ(r.axis_limits[0].block, 2);
  EXPECT_EQ(r.axis_limits[0].axis, 'X');
  EXPECT_NEAR(r.axis_limits[0].value, 65.0, 1e-9);
  EXPECT_EQ(r.axis_limits[1].line, 4);
  EXPECT_DOUBLE_EQ(r.axis_limits[1].value, 70.0);
  EXPECT_DOUBLE_EQ(r.axis_limits[1].max, 60.0);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings.back().find("limits"), std::string::npos);
}

// A 3-axis program under tool length offsets moves the spindle nose (its targets are read as the tips, a
// gauge length below): the limits are the nose's. Checking the tips had reported a Z the machine never
// reaches and missed one it does (found by black-box testing).
TEST(AxisLimits, ThreeAxisProgramWithLengthOffsetsIsCheckedAtTheNose) {
  const Tool tool = test::ball_tool(3, 10, 3, 40, {});
  Scene s = test::box_scene({0, 0, 0}, {50, 50, 10}, tool);
  MachineSpec m;
  m.limits['Z'] = {-100, -10};
  s.machine = m;
  Program p;
  p.xyz_nose_programmed = true;
  p.start = {100, 100, -40, 0, 0, 0};
  p.blocks = {block(Motion::Rapid, {100, 100, -40, 0, 0, 0}, 1),    // nose at 0: beyond -10
              block(Motion::Rapid, {100, 100, -60, 0, 0, 0}, 2),    // nose at -20
              block(Motion::Rapid, {100, 100, -130, 0, 0, 0}, 3)};  // nose at -90 (the tip is beyond -100)
  const VerifyReport r = verify(s, p);
  ASSERT_EQ(r.axis_limits.size(), 1u);
  EXPECT_EQ(r.axis_limits[0].line, 1);
  EXPECT_NEAR(r.axis_limits[0].value, -40.0 + tool.length, 1e-9);
}

TEST(AxisLimits, TcpBlocksAreCheckedInMachineAxes) {
  Scene s = test::box_scene({-30, -30, 0}, {30, 30, 10}, test::ball_tool(3, 10, 3, 40, {}));
  MachineSpec m;
  m.kinematics = KinematicsType::TableTableAC;
  m.limits['A'] = {-100, 50};
  m.limits['X'] = {0, 100};
  s.machine = m;
  Program p;
  p.start = {20, 0, 50, 0, 0, 0};
  Block in = block(Motion::Linear, {20, 0, 50, 0, 0, 0}, 1);
  in.tcp = true;
  // The tip stays at part x = 20, but with the table turned half round the machine's X is -20.
  Block turned = block(Motion::Linear, {20, 0, 50, 0, 0, 180}, 2);
  turned.tcp = true;
  Block tilted = block(Motion::Linear, {20, 0, 50, -120, 0, 0}, 3);
  tilted.tcp = true;
  p.blocks = {in, turned, tilted};
  const VerifyReport r = verify(s, p);
  ASSERT_EQ(r.axis_limits.size(), 3u);
  EXPECT_EQ(r.axis_limits[0].block, 2);
  EXPECT_EQ(r.axis_limits[0].axis, 'X');
  EXPECT_NEAR(r.axis_limits[0].value, -20.0, 1e-6);
  // Block 3 turns C back from 180 while A tilts: X starts from -20 and comes back inside along it.
  EXPECT_EQ(r.axis_limits[1].block, 3);
  EXPECT_EQ(r.axis_limits[1].axis, 'X');
  EXPECT_LT(r.axis_limits[1].value, -19.9);
  EXPECT_EQ(r.axis_limits[2].block, 3);
  EXPECT_EQ(r.axis_limits[2].axis, 'A');
}

// A TCP swing of the table from C-80 to C80 with the tip at part x = 20: the machine's X is 3.5 at both
// ends and 20 half-way, beyond X 15; only the block's ends were checked before.
TEST(AxisLimits, TcpSwingIsCheckedAlongTheBlock) {
  Scene s = test::box_scene({-30, -30, 0}, {30, 30, 10}, test::ball_tool(3, 10, 3, 40, {}));
  MachineSpec m;
  m.kinematics = KinematicsType::TableTableAC;
  m.limits['X'] = {-100, 15};
  s.machine = m;
  Program p;
  p.start = {20, 0, 50, 0, 0, -80};
  Block in = block(Motion::Linear, {20, 0, 50, 0, 0, -80}, 1);
  in.tcp = true;
  Block swing = block(Motion::Linear, {20, 0, 50, 0, 0, 80}, 2);
  swing.tcp = true;
  p.blocks = {in, swing};
  const VerifyReport r = verify(s, p);
  ASSERT_EQ(r.axis_limits.size(), 1u);
  EXPECT_EQ(r.axis_limits[0].block, 2);
  EXPECT_EQ(r.axis_limits[0].axis, 'X');
  EXPECT_GT(r.axis_limits[0].value, 19.9);
}

}  // namespace
}  // namespace tf
