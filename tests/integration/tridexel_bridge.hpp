// Runs a grinding program through the tri-dexel verifier (tests and bench_grind): the wheel becomes a flat
// "tool" (a cylinder of the wheel's radius and width, so only sharp-cornered wheels compare exactly), the
// six grinder axes ride in the verifier's joints (x, y, z = X, Y, Z; a = A; b = W; c = U), and the forward
// map is the grinder's own kinematics. Both simulators interpolate every axis linearly per block.
#pragma once
#include "tiltfield/grind/sections.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf::grind::testing {

inline Axes to_axes(const Joints& j) { return {j.x, j.y, j.z, j.c, j.a, j.b}; }
inline Joints to_joints(const Axes& a) {
  Joints j;
  j.x = a.x, j.y = a.y, j.z = a.z, j.a = a.a, j.b = a.w, j.c = a.u;
  return j;
}

inline VerifyReport tridexel_report(const GrindScene& g, double resolution, double sweep_tolerance) {
  Scene scene;
  scene.stock.kind = Stock::Kind::Cylinder;
  scene.stock.cylinder = {Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), g.blank.radius, g.blank.length};
  scene.tool.cutter = FlatCutter{g.wheel.radius};
  scene.tool.flute_length = g.wheel.thickness;
  scene.tool.shank_radius = 0.01;  // non-cutting, a hair above the wheel's upper face
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
  vopt.resolution = resolution;
  vopt.sweep.tolerance = sweep_tolerance;
  return verify_program(scene, program, forward, vopt).report;
}

// Removed volume by the sections: the blank polygon's prism minus the trapezoid rule over the section areas.
inline double sections_removed(const SectionStack& stack) {
  double kept = 0;
  for (size_t i = 1; i < stack.sections.size(); ++i)
    kept += 0.5 * (section_area(stack.sections[i]) + section_area(stack.sections[i - 1])) *
            (stack.sections[i].z - stack.sections[i - 1].z);
  return section_area(stack.sections.front()) * stack.blank.length - kept;
}

}  // namespace tf::grind::testing
