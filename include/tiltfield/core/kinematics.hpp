// tiltfield: the one kinematics implementation (forward and inverse), shared by the post-processor and
// the verifier.
//
// Units: X Y Z in mm, A B C in degrees. The part frame is the frame the scene's geometry is in; the
// machine frame is the controller's. The tool pose is the tool tip and the unit tool axis (tip toward
// spindle) in the part frame. At A = B = C = 0 every machine's tool axis is +Z and the part frame is
// parallel to the machine frame. L is the gauge length (tip to spindle nose).
//
// Conventions (docs/post.md has the derivations). Rx, Ry, Rz are right-handed rotations about the
// machine's +X, +Y, +Z; r = MachineSpec::pivot, d = MachineSpec::tilt_offset, t = table_center,
// Lp = head_pivot_length, p the tip in the part frame, u the tool axis in the machine frame.
//   xyz            X Y Z = p (the tool tip, as 3-axis programs give it); axis always +Z.
//   table-table-ac LinuxCNC xyzac-trt-kins (2.9, default "unconventional" directions), tool-offset = L:
//                  XYZ = Rx(A) Rz(C) (p - r) + r + (I - Rx(A)) d + L ez.
//                  Axis in the part frame = (sin A sin C, sin A cos C, cos A).
//   table-table-bc LinuxCNC xyzbc-trt-kins: XYZ = Ry(B) Rz(C) (p - r) + r + (I - Ry(B)) d + L ez.
//                  Axis in the part frame = (-sin B cos C, sin B sin C, cos B).
//   head-table-bc  swivel head B (right-handed about +Y), table C turning like the trt tables:
//                  q = Rz(C) (p - t) + t (the tip in the machine frame), u = Ry(B) ez,
//                  XYZ = q + (L + Lp) u - Lp ez (the spindle nose's position when B = 0).
//                  Axis in the part frame = (sin B cos C, -sin B sin C, cos B).
//   head-head-ac   fork head: C about +Z carrying A about +X, axes meeting at the head pivot:
//                  u = Rz(C) Rx(A) ez, XYZ = p + (L + Lp) u - Lp ez.
//                  Axis = (sin A sin C, -sin A cos C, cos A).
// So for every 5-axis type the joint XYZ equal the spindle nose (tip + L along the axis) whenever the
// rotaries are at 0, and LinuxCNC running identity kinematics (or trivkins) moves a trt machine exactly
// as its xyzac-trt/xyzbc-trt kinematics would with tool-offset = L and the same rot-point/offset pins.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "tiltfield/core/machine.hpp"

namespace tf {

// Axis values as the controller sees them. Rotaries the machine lacks stay 0.
struct Joints {
  double x = 0, y = 0, z = 0;  // mm
  double a = 0, b = 0, c = 0;  // deg
  double rotary(char letter) const { return letter == 'A' ? a : letter == 'B' ? b : c; }
  // Axis i in the order X Y Z A B C (i in 0..5).
  double& axis(int i) {
    double* const v[6] = {&x, &y, &z, &a, &b, &c};
    return *v[i];
  }
  double axis(int i) const { return const_cast<Joints*>(this)->axis(i); }
};

struct ToolPose {
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();     // part frame, mm
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   // part frame, unit, tip toward spindle
};

struct InverseOptions {
  // Below this angle (deg) of the tilting axis from 0, the pose is at the singular pole: the C axis is
  // held at the previous value instead of swinging, and the tilting axis takes the angle that brings
  // the tool axis nearest to the wanted one (the axis error is then at most this angle). For the xyz
  // machine: the largest accepted angle between the wanted axis and +Z.
  double pole_tolerance_deg = 0.01;
};

class Kinematics {
 public:
  // gauge_length: the tool's gauge length (tip to spindle nose / holder face), mm. Joint programs for
  // head machines and LinuxCNC's trt kinematics with tool-length offset need it.
  Kinematics(MachineSpec machine, double gauge_length);

  const MachineSpec& machine() const { return machine_; }
  double gauge_length() const { return gauge_length_; }

  // Joint values -> tool pose in the part frame.
  ToolPose forward(const Joints& j) const;

  // Tool pose -> every joint solution (two for a 5-axis machine away from the pole, one continuum at the
  // pole, for which the solution with C = previous.c is returned). Rotary values are unwound to be
  // nearest to `previous` (continuous axes) and solutions outside the limits are dropped. Empty when the
  // pose is unreachable.
  std::vector<Joints> inverse(const ToolPose& pose, const Joints& previous, const InverseOptions& options = {}) const;

  // The solution nearest to `previous` (by rotary motion), or nullopt when unreachable.
  std::optional<Joints> inverse_nearest(const ToolPose& pose, const Joints& previous,
                                        const InverseOptions& options = {}) const;

  // The joints with the C axis held at `c` (deg, taken as given, not unwound) and the tilting axis at the
  // angle that brings the tool axis nearest to pose.axis (the tip is exact). Used at the singular pole,
  // where C is free. The tilting axis is unwound toward previous. nullopt when outside the limits, and
  // for machines without C (xyz).
  std::optional<Joints> inverse_with_c(const ToolPose& pose, double c, const Joints& previous) const;

  bool within_limits(const Joints& j) const;

  // Angle (deg) between the tool axis and the pole (+Z of the rotary chain at 0): |tilt| of any solution.
  static double pole_angle_deg(const Eigen::Vector3d& axis);

 private:
  MachineSpec machine_;
  double gauge_length_;
};

// An axis of a joint position beyond its limit.
struct AxisOutside {
  char axis;     // X Y Z A B C
  double value;  // mm or deg
  AxisLimit limit;
};
// The axes of j beyond machine.limits by more than `slack` (mm or deg), in the order X Y Z A B C: what the
// post names when it cannot reach a point and what the verifier reports.
std::vector<AxisOutside> axes_outside_limits(const MachineSpec& machine, const Joints& j, double slack = 0.0);

// In: `forward` (joints -> tool pose in the part frame: Kinematics::forward, or a per-tool map), the
// rotaries of `at` (its X Y Z ignored) and a tool tip in the part frame, mm. Out: `at` with the machine's
// X Y Z that put the tip there: what a controller under tool-centre-point control (G43.4, M428) drives
// for a programmed tip. Every kinematics here moves the tip affinely with X Y Z at fixed rotaries.
Joints joints_for_tip(const std::function<ToolPose(const Joints&)>& forward, Joints at, const Eigen::Vector3d& tip);

// The rotary distance between two joint sets, deg: the sum of |difference| over A, B and C.
double rotary_distance(const Joints& a, const Joints& b);

}  // namespace tf
