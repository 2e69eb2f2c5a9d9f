// tiltfield: the one kinematics implementation (forward and inverse), shared by the post-processor and
// the verifier. Implemented in planner/kinematics*.cpp (issue 4).
//
// Units: X Y Z in mm, A B C in degrees. The part frame is the frame the scene's geometry is in; the
// machine frame is the controller's. The tool pose is the tool tip and the unit tool axis (tip toward
// spindle) in the part frame.
#pragma once
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "tiltfield/machine.hpp"

namespace tf {

// Axis values as the controller sees them. Rotaries the machine lacks stay 0.
struct Joints {
  double x = 0, y = 0, z = 0;  // mm
  double a = 0, b = 0, c = 0;  // deg
  double rotary(char letter) const { return letter == 'A' ? a : letter == 'B' ? b : c; }
};

struct ToolPose {
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();     // part frame, mm
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   // part frame, unit, tip toward spindle
};

struct InverseOptions {
  // Below this angle (deg) of the tilting axis from 0, the pose is at the singular pole: the C axis is
  // held at (or interpolated from) the previous value instead of swinging.
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

  bool within_limits(const Joints& j) const;

 private:
  MachineSpec machine_;
  double gauge_length_;
};

}  // namespace tf
