// tiltfield (internal to the post-processor): the steps post_program() chains.
#pragma once
#include <cstdio>
#include <cstdlib>
#include <Eigen/Geometry>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/post/post.hpp"

namespace tf::post_detail {

// Chooses one joint solution per pose: the two solutions of every row, unwinding and limits, by dynamic
// programming over the rows for the least total rotary motion (so a forced change of configuration
// happens where it costs least); rows within the pole tolerance get C held or interpolated (PoleMode)
// and the tilt that best matches their axis. Throws PostRowError for a row without any solution.
std::vector<Joints> choose_joints(const std::vector<ToolPose>& poses, const Kinematics& kin, const PostOptions& options);

// The tilting rotary of a five-axis machine's joints (A or B), deg.
inline double tilt_of(const Joints& j, KinematicsType k) {
  return k == KinematicsType::TableTableAC || k == KinematicsType::HeadHeadAC ? j.a : j.b;
}

// Every joint solution of a pose within the limits: both solutions and, for a C axis with limits, each
// of its turns (continuous axes: the turn nearest `near`).
std::vector<Joints> all_solutions(const ToolPose& pose, const Kinematics& kin, const Joints& near);

// Angle (deg) from the pole +Z to the great-circle arc between unit axes a and b: how close the wanted
// axis comes to the singular pole on the move.
double arc_pole_distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

// Why `pose` has no joint solution on this machine, in plain words (for PostRowError).
std::string unreachable_reason(const ToolPose& pose, const Kinematics& kin, const PostOptions& options);

// Axis words are written with this many decimals (gcode_writer); the controller moves to the value rounded
// there, so blocks are timed and the tip solved at that value (program_builder).
inline constexpr int kAxisDecimals = 4;
inline constexpr double kAxisScale = 1e4;  // 10^kAxisDecimals
inline constexpr double kAxisUnit = 1.0 / kAxisScale;
// `value` as written: rounded to kAxisDecimals in the frame of the work offset `origin`, by the writer's
// own formatting (a half unit, such as 2.50005, rounds as printf rounds the binary value: std::round had
// read 2.5001 where 2.5000 was written, and the TCP feed cap had taken a moving tip for a still one).
inline double as_written(double value, double origin) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", kAxisDecimals, value - origin);
  return std::strtod(buf, nullptr) + origin;
}

// Sampling a block can miss a little of the true maximum between samples: the linearisation accepts a
// block only below this share of the tolerances.
inline constexpr double kLinearizeSafety = 0.95;

struct LinearizeOptions {
  double tip_tolerance_mm = 0.01;  // +infinity: do not check the tip (tcp dialect)
  double axis_tolerance_deg = 0.1;
  double pole_tolerance_deg = 0.01;
  int samples = 9;                 // interior sample points per candidate block
  int max_depth = 18;              // bisections per segment before giving up
};

// One posted point: the intended pose and the joints that reach it.
struct PosedJoints {
  ToolPose pose;
  Joints joints;
};

// Splits the joint-linear move j0 -> j1 (reaching poses p0 -> p1) by bisection until every sub-block
// deviates from the straight tip segment / great-circle axis by at most the tolerances. Appends the
// sub-block ends (not j0, ending with j1) to `out`. Returns false (out unchanged) when it does not
// converge within max_depth (a discontinuous move, e.g. a change of configuration) or an intermediate
// pose is unreachable.
bool linearize(const Kinematics& kin, const ToolPose& p0, const Joints& j0, const ToolPose& p1, const Joints& j1,
               const LinearizeOptions& options, std::vector<PosedJoints>& out);

// The joints that put the tool at `pose` with the rotaries of `at` (the tilt re-derived exactly, C kept);
// nullopt when outside the limits. For the xyz machine: the tip.
std::optional<Joints> joints_at_rotaries(const Kinematics& kin, const ToolPose& pose, const Joints& at);

// The largest projection of the box's points on `dir` (unit): the box's extent along a tool axis, mm.
inline double max_projection(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& dir) {
  const Eigen::Vector3d c = box.center(), h = 0.5 * box.sizes();
  return c.dot(dir) + h.x() * std::abs(dir.x()) + h.y() * std::abs(dir.y()) + h.z() * std::abs(dir.z());
}

}  // namespace tf::post_detail
