// Cross-check with the tri-dexel verifier: the same grinding program, the wheel given to the verifier as a
// flat "tool" (a cylinder of the wheel's radius and width), removes the same volume as the section
// simulation. Both use a sharp-cornered wheel (edge_radius 0), the one wheel shape both represent exactly:
// the verifier's tools round only the tip end. The program here moves by translations only (three straight
// flutes, a swivelled gash plunge, a notch), which the verifier sweeps exactly and quickly; the bundled
// end mill's helical program is cross-checked the same way in bench_grind (it takes minutes there).
#include <gtest/gtest.h>

#include "grind_test_util.hpp"
#include "tiltfield/sections.hpp"
#include "tiltfield/verify.hpp"

namespace tf::grind {
namespace {

// The grinder's six axes ride in the verifier's joints as x, y, z = X, Y, Z; a = A; b = W; c = U. Every
// axis is interpolated linearly per block in both simulators.
Axes to_axes(const Joints& j) { return {j.x, j.y, j.z, j.c, j.a, j.b}; }
Joints to_joints(const Axes& a) {
  Joints j;
  j.x = a.x, j.y = a.y, j.z = a.z, j.a = a.a, j.b = a.w, j.c = a.u;
  return j;
}

const char* kProgram = R"(
OP fluting flute 1
G0 X1.5 Y60 Z50 A0
G1 Y43.5
G1 Z12
G0 Y150
OP fluting flute 2
G0 A120
G0 Y43.5 Z50
G1 Z12
G0 Y150
OP fluting flute 3
G0 A240
G0 Y43.5 Z50
G1 Z12
G0 Y150
OP gashing gash
G0 X18.955 Y60 Z7.77 A40 W60
G1 Y41.2
G0 Y150
OP notching notch
G0 X0 Y150 Z59.7 A0 W0
G0 Y8
G1 Y-8
G0 Y150
)";

TEST(TriDexelCrossCheck, SameRemovedVolumeWithinOnePercent) {
  const GrindScene g = testing::make_scene(5.0, 20.0, 40.0, 3.0, 0.0, kProgram, Axes{0, 150, 0, 0, 0, 0});

  SectionOptions sopt;
  sopt.spacing = 0.05;
  const SectionStack stack = simulate_sections(g, sopt);
  double kept = 0;  // trapezoid rule over the section areas
  for (size_t i = 1; i < stack.sections.size(); ++i)
    kept += 0.5 * (section_area(stack.sections[i]) + section_area(stack.sections[i - 1])) *
            (stack.sections[i].z - stack.sections[i - 1].z);
  const double removed_sections = section_area(stack.sections.front()) * g.blank.length - kept;

  Scene scene;
  scene.stock.kind = Stock::Kind::Cylinder;
  scene.stock.cylinder = {Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), g.blank.radius, g.blank.length};
  scene.tool.cutter = FlatCutter{g.wheel.radius};
  scene.tool.flute_length = g.wheel.thickness;
  scene.tool.shank_radius = 0.01;  // non-cutting, inside the wheel's hole in practice
  scene.tool.length = g.wheel.thickness + 0.01;
  scene.tool.holder.clear();
  Program program;
  program.start = to_joints(g.start);
  for (const Operation& op : g.operations)
    for (const Move& m : op.moves) {
      Block b;
      b.line = m.line;
      b.motion = m.rapid ? Motion::Rapid : Motion::Linear;
      b.target = to_joints(m.target);
      b.feed = 300;
      program.blocks.push_back(b);
    }
  const double half = 0.5 * g.wheel.thickness;
  const ForwardFn forward = [half](const Joints& j) {
    const WheelPose p = wheel_pose(to_axes(j));
    return ToolPose{p.centre - half * p.axis, p.axis};  // the "tip" is the centre of the wheel's lower face
  };
  VerifyOptions vopt;
  vopt.resolution = 0.1;
  vopt.sweep.tolerance = 0.01;
  const VerifyResult v = verify_program(scene, program, forward, vopt);
  const double rel = std::abs(v.report.removed_volume_mm3 - removed_sections) / removed_sections;
  std::printf("tri-dexel cross-check: removed %.3f mm3 (tri-dexel, %.2f mm rays, sweep error %.4f mm) vs %.3f mm3 "
              "(sections, 0.05 mm), rel. diff %.4f\n",
              v.report.removed_volume_mm3, vopt.resolution, v.report.sweep_error_mm, removed_sections, rel);
  EXPECT_LT(rel, 0.01);
}

}  // namespace
}  // namespace tf::grind
