// Collisions (holder in the stock, a rapid through the stock, a fixture touched), a clean program,
// gouges against the design, and a hand-written 5-axis TCP program with G93.
#include <gtest/gtest.h>

#include <numbers>

#include "helpers.hpp"
#include "tiltfield/gcode.hpp"
#include "tiltfield/verify.hpp"

namespace tf {
namespace {

// Ball R 3, flutes to 12, shank R 3 to the gauge length 20, holder R 10 x 30.
Tool short_tool() { return test::ball_tool(3, 12, 3, 20, {{10, 30}}); }

VerifyResult run(const Scene& s, const std::string& text, VerifyOptions o = {}) {
  o.resolution = 0.2;
  return verify_program(s, parse_gcode(text, "c.ngc", MachineSpec{}), forward_xyz, o);
}

TEST(Collisions, HolderDipsIntoTheStock) {
  const Scene s = test::box_scene({0, 0, 0}, {50, 50, 30}, short_tool());
  // Line 3 plunges the tip to z = 5: the holder face (tip + 20) is 5 mm below the top.
  const VerifyResult r = run(s, "G0 X25 Y25 Z60\nG1 Z40 F500\nG1 Z5\nG1 Z40\n");
  ASSERT_FALSE(r.report.collisions.empty());
  bool holder = false;
  // The crash destroys the material the holder met, so the retract (block 4) is clean.
  for (const Collision& c : r.report.collisions) {
    EXPECT_EQ(c.block, 3);
    EXPECT_EQ(c.line, 3);
    EXPECT_FALSE(c.rapid);
    EXPECT_EQ(c.with, HitWith::Stock);
    EXPECT_NE(c.component, ToolComponent::Ball);  // the cutting end is no collision in a feed move
    if (c.component == ToolComponent::Holder) {
      holder = true;
      EXPECT_NEAR(c.depth_mm, 5.0, 0.25);
    }
  }
  EXPECT_TRUE(holder);
  EXPECT_TRUE(r.report.per_block[2].collision);
  EXPECT_FALSE(r.report.per_block[3].collision);
}

TEST(Collisions, RapidThroughTheStock) {
  const Scene s = test::box_scene({0, 0, 0}, {50, 50, 30}, short_tool());
  const VerifyResult r = run(s, "G0 X-10 Y25 Z60\nG0 Z25\nG0 X60\nG0 Z60\n");
  ASSERT_FALSE(r.report.collisions.empty());
  for (const Collision& c : r.report.collisions) {
    EXPECT_EQ(c.block, 3);
    EXPECT_EQ(c.line, 3);
    EXPECT_TRUE(c.rapid);
    EXPECT_EQ(c.with, HitWith::Stock);
  }
  EXPECT_EQ(r.report.collisions.front().component, ToolComponent::Ball);
  EXPECT_NEAR(r.report.collisions.front().depth_mm, 5.0, 0.25);  // ball 5 mm into the top... across
}

TEST(Collisions, ToolTouchesAFixture) {
  Scene s = test::box_scene({0, 0, 0}, {50, 50, 30}, short_tool());
  s.fixtures.push_back(test::box_mesh({55, 0, 0}, {70, 50, 20}));  // a clamp beside the stock
  const VerifyResult r = run(s, "G0 X60 Y25 Z50\nG1 Z25 F500\nG1 Z18\nG1 Z50\n");
  ASSERT_FALSE(r.report.collisions.empty());
  EXPECT_EQ(r.report.collisions.front().block, 3);
  for (const Collision& c : r.report.collisions) {
    // The plunge into the clamp (line 3) and the retract out of it (line 4).
    EXPECT_EQ(c.line, c.block);
    EXPECT_TRUE(c.block == 3 || c.block == 4);
    EXPECT_EQ(c.with, HitWith::Fixture);
    EXPECT_EQ(c.component, ToolComponent::Ball);
    EXPECT_NEAR(c.depth_mm, 2.0, 0.25);
  }
  VerifyOptions o;
  o.stop_at_first_collision = true;
  const VerifyResult stopped = run(s, "G0 X60 Y25 Z50\nG1 Z25 F500\nG1 Z18\nG1 Z50\nG1 Z18\n", o);
  EXPECT_EQ(stopped.report.blocks, 3);
  EXPECT_TRUE(stopped.report.stopped_early);
}

TEST(Collisions, CleanProgramReportsNone) {
  Scene s = test::box_scene({0, 0, 0}, {50, 50, 30}, short_tool());
  s.fixtures.push_back(test::box_mesh({55, 0, 0}, {70, 50, 20}));
  s.check_surfaces.push_back(test::box_mesh({0, 60, 0}, {50, 70, 40}));
  s.design = test::box_mesh({-1, -1, -1}, {51, 51, 27});  // the finished top at z = 27
  const VerifyResult r = run(s, "G0 X-5 Y10 Z40\nG1 Z27 F800\nG1 X55\nG1 Y20\nG1 X-5\nG0 Z40\n");
  EXPECT_TRUE(r.report.collisions.empty());
  EXPECT_TRUE(r.report.gouges.empty());
  EXPECT_LT(r.report.max_gouge_mm, 0.01);
  EXPECT_GT(r.report.removed_volume_mm3, 0);
  EXPECT_GT(r.report.excess.samples, 0u);
  EXPECT_GT(r.report.excess.max_mm, 2.9);  // most of the top is still uncut (3 mm above the design)
}

TEST(Collisions, GougeAgainstTheDesign) {
  Scene s = test::box_scene({0, 0, 0}, {50, 50, 30}, short_tool());
  s.design = test::box_mesh({-1, -1, -1}, {51, 51, 27});
  const VerifyResult r = run(s, "G0 X10 Y25 Z40\nG1 Z27 F800\nG1 X20\nG1 Z26.5\nG1 X30\nG0 Z40\n");
  ASSERT_EQ(r.report.gouges.size(), 2u);  // the plunge to 26.5 and the move at 26.5
  EXPECT_EQ(r.report.gouges[0].line, 4);
  EXPECT_EQ(r.report.gouges[1].line, 5);
  EXPECT_NEAR(r.report.max_gouge_mm, 0.5, 0.02);
}

// A TCP program as another CAM system writes it: G43.4, inverse-time feed, tool tip in the part frame
// plus rotary angles. The machine's "A" tilts the axis about X (a stand-in forward map until the shared
// kinematics is merged).
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
