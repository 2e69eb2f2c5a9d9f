// Linearisation: the controller interpolates the joints linearly between blocks, so the tool tip
// leaves the intended straight segment and the axis the intended great circle; blocks are bisected
// until both stay within the tolerances.
#include <cmath>
#include <limits>

#include "tiltfield/core/angles.hpp"
#include "post_internal.hpp"
#include "tiltfield/core/local_frame.hpp"

namespace tf {
namespace {


double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return angle_between(a, b) / kDeg;
}

Joints lerp(const Joints& a, const Joints& b, double s) {
  Joints j;
  j.x = a.x + (b.x - a.x) * s;
  j.y = a.y + (b.y - a.y) * s;
  j.z = a.z + (b.z - a.z) * s;
  j.a = a.a + (b.a - a.a) * s;
  j.b = a.b + (b.b - a.b) * s;
  j.c = a.c + (b.c - a.c) * s;
  return j;
}

}  // namespace

Deviation joint_deviation(const Kinematics& kin, const Joints& j0, const Joints& j1, const ToolPose& p0,
                          const ToolPose& p1, int samples) {
  Deviation d;
  for (int k = 1; k <= samples; ++k) {
    const double s = double(k) / double(samples + 1);
    const ToolPose got = kin.forward(lerp(j0, j1, s));
    const Eigen::Vector3d tip = p0.tip + (p1.tip - p0.tip) * s;
    d.tip_mm = std::max(d.tip_mm, (got.tip - tip).norm());
    d.axis_deg = std::max(d.axis_deg, angle_deg(got.axis, slerp_axis(p0.axis, p1.axis, s)));
  }
  return d;
}

namespace post_detail {
namespace {

bool near_pole(const ToolPose& p0, const ToolPose& p1, double pole_tolerance_deg) {
  return arc_pole_distance(p0.axis, p1.axis) < pole_tolerance_deg;
}

bool refine(const Kinematics& kin, const ToolPose& p0, const Joints& j0, const ToolPose& p1, const Joints& j1,
            const LinearizeOptions& o, int depth, std::vector<PosedJoints>& out) {
  const Deviation d = joint_deviation(kin, j0, j1, p0, p1, o.samples);
  // Within the pole cone the rows themselves carry an axis error up to the pole tolerance.
  const double axis_allowed = o.axis_tolerance_deg + (near_pole(p0, p1, o.pole_tolerance_deg) ? o.pole_tolerance_deg : 0.0);
  if (d.tip_mm <= kLinearizeSafety * o.tip_tolerance_mm && d.axis_deg <= kLinearizeSafety * axis_allowed) {
    out.push_back({p1, j1});
    return true;
  }
  if (depth >= o.max_depth) return false;
  const ToolPose pm{0.5 * (p0.tip + p1.tip), slerp_axis(p0.axis, p1.axis, 0.5)};
  const Joints mid = lerp(j0, j1, 0.5);
  std::optional<Joints> jm;
  const KinematicsType k = kin.machine().kinematics;
  auto tilt = [k](const Joints& j) {
    return std::remainder(k == KinematicsType::TableTableAC || k == KinematicsType::HeadHeadAC ? j.a : j.b, 360.0);
  };
  const double pole_angle = Kinematics::pole_angle_deg(pm.axis);
  if (k != KinematicsType::XYZ && (pole_angle < o.pole_tolerance_deg || std::hypot(pm.axis.x(), pm.axis.y()) < 1e-12 ||
                                   tilt(j0) * tilt(j1) < 0.0)) {
    // In the cone, or on a move that changes to the mirror solution (the tilt passes 0 at a held C, which
    // the joint solutions take only where the wanted axis passes the pole within the tolerances): C as
    // the joints interpolate it, the tilt that fits best. Solved exactly, the points of such a move swung
    // C 30 deg either way, following the wanted axis's azimuth round the pole (black-box testing).
    jm = kin.inverse_with_c(pm, mid.c, mid);
  } else if (k != KinematicsType::XYZ && pole_angle < o.pole_tolerance_deg + o.axis_tolerance_deg) {
    // Just outside the cone the exact C is the axis's azimuth, which turns fast around the pole: on a
    // head-head machine the points bisected beside it swung C 28 deg either way with A within 0.15 deg.
    // C interpolated, with the tilt that fits best, is kept where it is within half the axis tolerance.
    const std::optional<Joints> held = kin.inverse_with_c(pm, mid.c, mid);
    if (held && angle_deg(kin.forward(*held).axis, pm.axis) <= 0.5 * o.axis_tolerance_deg) jm = held;
  }
  if (!jm) {
    InverseOptions exact;
    exact.pole_tolerance_deg = kin.machine().kinematics == KinematicsType::XYZ ? o.pole_tolerance_deg : 0.0;
    // Stay on the ends' solution branch (sign of the tilt) when they share one: near the pole the
    // nearest solution can be the mirror one, and a branch change inside the move never converges.
    const bool same_branch = (tilt(j0) > 0) == (tilt(j1) > 0) && tilt(j0) != 0 && tilt(j1) != 0;
    double best = std::numeric_limits<double>::infinity();
    for (const Joints& c : kin.inverse(pm, mid, exact)) {
      const double d = rotary_distance(c, mid) + (same_branch && (tilt(c) > 0) != (tilt(j0) > 0) ? 1e6 : 0.0);
      if (d < best) {
        best = d;
        jm = c;
      }
    }
  }
  if (!jm) return false;
  return refine(kin, p0, j0, pm, *jm, o, depth + 1, out) && refine(kin, pm, *jm, p1, j1, o, depth + 1, out);
}

}  // namespace

bool linearize(const Kinematics& kin, const ToolPose& p0, const Joints& j0, const ToolPose& p1, const Joints& j1,
               const LinearizeOptions& options, std::vector<PosedJoints>& out) {
  const size_t keep = out.size();
  if (refine(kin, p0, j0, p1, j1, options, 0, out)) return true;
  out.resize(keep);
  return false;
}

std::optional<Joints> joints_at_rotaries(const Kinematics& kin, const ToolPose& pose, const Joints& at) {
  if (kin.machine().kinematics == KinematicsType::XYZ) {
    Joints j;
    j.x = pose.tip.x();
    j.y = pose.tip.y();
    j.z = pose.tip.z();
    if (!kin.within_limits(j)) return std::nullopt;
    return j;
  }
  return kin.inverse_with_c(pose, at.c, at);
}

}  // namespace post_detail
}  // namespace tf
