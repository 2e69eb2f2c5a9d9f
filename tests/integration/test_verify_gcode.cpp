// Programs read by the G-code reader and simulated: a 5-axis TCP program with G93 as another CAM system
// writes it.
#include <gtest/gtest.h>

#include <numbers>

#include "dexel/helpers.hpp"
#include "tiltfield/dexel/verify.hpp"
#include "tiltfield/gcode/gcode.hpp"

namespace tf {
namespace {

// A TCP program as another CAM system writes it: G43.4, inverse-time feed, tool tip in the part frame
// plus rotary angles. The machine's "A" tilts the axis about X (a stand-in forward map, independent of any
// machine's pivots).
TEST(Collisions, FiveAxisTcpProgramWithG93) {
  Scene s = test::box_scene({0, 0, 0}, {60, 40, 20}, test::ball_tool(3, 20, 3, 60, {{15, 40}}));
  MachineSpec m;
  m.kinematics = KinematicsType::TableTableAC;
  const std::string text =
      "%\n(5-axis finishing, TCP)\nG21 G90 G17\nT1 M6\nS15000 M3\nG43.4 H1\n"
      "G0 X5 Y20 Z40 A0 C0\nG1 Z19 F600\nG93\n"
      "N100 G1 X15 Y20 Z19 A10 F60\nN110 G1 X25 A20 F60\nN120 G1 X35 A20 F120\nN130 G1 X45 A0 F60\n"
      "G94 G0 Z40\nG49\nM5\nM30\n%\n";
  const Program p = parse_gcode(text, "tcp.ngc", m);
  ASSERT_EQ(p.blocks.size(), 7u);
  const ForwardFn fwd = [](const Joints& j) {
    const double a = j.a * std::numbers::pi / 180.0;
    return ToolPose{Eigen::Vector3d(j.x, j.y, j.z), Eigen::Vector3d(0, -std::sin(a), std::cos(a))};
  };
  VerifyOptions o;
  o.resolution = 0.2;
  const VerifyResult r = verify_program(s, p, fwd, o);
  EXPECT_TRUE(r.report.collisions.empty());
  // The tip moves 1 mm deep along X from 5 to 45 whatever the tilt (TCP): the ball's groove.
  const double groove_section = 9 * std::acos(2.0 / 3.0) - 2 * std::sqrt(5.0);  // circle segment, depth 1
  EXPECT_GT(r.report.removed_volume_mm3, groove_section * 40 * 0.95);
  EXPECT_EQ(r.report.per_block[2].line, 10);
  EXPECT_NEAR(r.report.per_block[2].minutes, 1.0 / 60.0, 1e-12);
  EXPECT_GT(r.report.per_block[2].substeps, 1);
  EXPECT_EQ(r.report.per_block[4].substeps, 1);  // constant axis: one exact step
  EXPECT_GT(r.report.per_block[5].substeps, 1);
}

}  // namespace
}  // namespace tf
