// Cross-check with the tri-dexel verifier: the bundled end mill's program, the wheel given to the verifier
// as a flat "tool" (a cylinder of the wheel's radius and width), removes the same volume as the section
// simulation. Both use a sharp-cornered wheel here (edge_radius 0), the one wheel shape both can represent
// exactly: the verifier's tools round only the tip end.
#include <gtest/gtest.h>

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

TEST(TriDexelCrossCheck, SameRemovedVolumeWithinOnePercent) {
  GrindScene g = load_grind_scene(std::string(TILTFIELD_SOURCE_DIR) + "/scenes/grinding/endmill.json");
  g.wheel.edge_radius = 0.0;
  g.wheel.profile = make_wheel_profile(g.wheel.radius, g.wheel.thickness, 0.0);

  SectionOptions sopt;
  sopt.spacing = 0.1;
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
  vopt.resolution = 0.2;
  vopt.sweep.tolerance = 0.05;
  const VerifyResult v = verify_program(scene, program, forward, vopt);
  const double rel = std::abs(v.report.removed_volume_mm3 - removed_sections) / removed_sections;
  std::printf("tri-dexel cross-check: removed %.3f mm3 (tri-dexel, %.2f mm rays, sweep error %.4f mm) vs %.3f mm3 "
              "(sections, 0.1 mm), rel. diff %.4f\n",
              v.report.removed_volume_mm3, vopt.resolution, v.report.sweep_error_mm, removed_sections, rel);
  EXPECT_LT(rel, 0.01);
}

}  // namespace
}  // namespace tf::grind
