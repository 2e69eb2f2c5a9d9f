// The machine kinematics (see tiltfield/core/kinematics.hpp for the conventions of every type).
//
// Every 5-axis type here shares one structure: a tilting axis T (A or B) and a C axis about +Z, with
// the tool axis in the part frame = cos(T) ez + sin(T) w(C), w(C) a unit horizontal vector that turns
// with C. So the inverse is the same for all: T = ±(angle of the axis from +Z), C from the horizontal
// part of the axis, and X Y Z from the tip through the (affine) joint map.
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "tiltfield/core/angles.hpp"
#include "tiltfield/core/kinematics.hpp"

namespace tf {
namespace {

constexpr double kPi = 3.14159265358979323846;
// A horizontal axis component below this (unit vector length) is the pole itself: C is undefined.
constexpr double kPoleEpsilon = 1e-12;

Eigen::Matrix3d rot(const Eigen::Vector3d& axis, double deg) {
  return Eigen::AngleAxisd(deg * kDeg, axis).toRotationMatrix();
}

bool is_table_table(KinematicsType k) {
  return k == KinematicsType::TableTableAC || k == KinematicsType::TableTableBC;
}

char tilt_letter(KinematicsType k) {
  return (k == KinematicsType::TableTableAC || k == KinematicsType::HeadHeadAC) ? 'A' : 'B';
}

// The machine axis the tilting rotary turns about.
Eigen::Vector3d tilt_axis(KinematicsType k) {
  return tilt_letter(k) == 'A' ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
}

double tilt_of(const Joints& j, KinematicsType k) { return tilt_letter(k) == 'A' ? j.a : j.b; }
void set_tilt(Joints& j, KinematicsType k, double v) { (tilt_letter(k) == 'A' ? j.a : j.b) = v; }

// w(C): the horizontal direction the tool axis leans toward for a positive tilt, in the part frame.
Eigen::Vector2d lean_direction(KinematicsType k, double c_deg) {
  const double s = std::sin(c_deg * kDeg), co = std::cos(c_deg * kDeg);
  switch (k) {
    case KinematicsType::TableTableAC: return {s, co};
    case KinematicsType::TableTableBC: return {-co, s};
    case KinematicsType::HeadTableBC: return {co, -s};
    case KinematicsType::HeadHeadAC: return {s, -co};
    case KinematicsType::XYZ: break;
  }
  return {0, 0};
}

// The inverse of lean_direction: C (deg, in (-180, 180]) for a unit horizontal direction w.
double c_of_lean(KinematicsType k, const Eigen::Vector2d& w) {
  switch (k) {
    case KinematicsType::TableTableAC: return std::atan2(w.x(), w.y()) / kDeg;
    case KinematicsType::TableTableBC: return std::atan2(w.y(), -w.x()) / kDeg;
    case KinematicsType::HeadTableBC: return std::atan2(-w.y(), w.x()) / kDeg;
    case KinematicsType::HeadHeadAC: return std::atan2(w.x(), -w.y()) / kDeg;
    case KinematicsType::XYZ: break;
  }
  return 0.0;
}

// The value v + 360 k nearest to `near` that lies within `limit`, or NaN when none does. The distance to
// `near` is convex in k, so the best turn is the unconstrained one clamped to the turns inside the limit
// (however many turns from 0 the limit lies).
double unwind(double v, double near, const AxisLimit& limit) {
  // An angle computed at a limit (acos(0.5) is 60.00000000000001; an axis read with 9 decimals is off by
  // about 1e-8 deg) is the limit: the planner's and the post's ways of computing it must not disagree
  // about a pose the machine reaches.
  constexpr double kSnap = 1e-6;  // deg: far below the 0.0001 deg a program is written with
  double k = std::round((near - v) / 360.0);
  const double k_lo = std::ceil((limit.min - kSnap - v) / 360.0), k_hi = std::floor((limit.max + kSnap - v) / 360.0);
  if (k_lo > k_hi) return std::numeric_limits<double>::quiet_NaN();
  k = std::clamp(k, k_lo, k_hi);  // infinite bounds leave k as it is
  const double cand = v + 360.0 * k;
  return std::clamp(cand, limit.min, limit.max);
}

AxisLimit limit_of(const MachineSpec& m, char letter) {
  auto it = m.limits.find(letter);
  return it == m.limits.end() ? AxisLimit{} : it->second;
}

// The rotation that takes part-frame directions to machine-frame directions (the table's turn), and the
// tool axis in the machine frame, for rotary values j.
Eigen::Matrix3d table_rotation(KinematicsType k, const Joints& j) {
  switch (k) {
    case KinematicsType::TableTableAC: return rot(Eigen::Vector3d::UnitX(), j.a) * rot(Eigen::Vector3d::UnitZ(), j.c);
    case KinematicsType::TableTableBC: return rot(Eigen::Vector3d::UnitY(), j.b) * rot(Eigen::Vector3d::UnitZ(), j.c);
    case KinematicsType::HeadTableBC: return rot(Eigen::Vector3d::UnitZ(), j.c);
    case KinematicsType::HeadHeadAC:
    case KinematicsType::XYZ: break;
  }
  return Eigen::Matrix3d::Identity();
}

Eigen::Vector3d machine_tool_axis(KinematicsType k, const Joints& j) {
  switch (k) {
    case KinematicsType::HeadTableBC: return rot(Eigen::Vector3d::UnitY(), j.b).col(2);
    case KinematicsType::HeadHeadAC: return (rot(Eigen::Vector3d::UnitZ(), j.c) * rot(Eigen::Vector3d::UnitX(), j.a)).col(2);
    default: break;
  }
  return Eigen::Vector3d::UnitZ();
}

}  // namespace

double rotary_distance(const Joints& a, const Joints& b) {
  return std::abs(a.a - b.a) + std::abs(a.b - b.b) + std::abs(a.c - b.c);
}

double Kinematics::pole_angle_deg(const Eigen::Vector3d& axis) {
  return std::atan2(std::hypot(axis.x(), axis.y()), axis.z()) / kDeg;
}

Kinematics::Kinematics(MachineSpec machine, double gauge_length)
    : machine_(std::move(machine)), gauge_length_(gauge_length) {}

ToolPose Kinematics::forward(const Joints& j) const {
  const KinematicsType k = machine_.kinematics;
  const Eigen::Vector3d J(j.x, j.y, j.z);
  const Eigen::Vector3d ez = Eigen::Vector3d::UnitZ();
  ToolPose pose;
  switch (k) {
    case KinematicsType::XYZ:
      pose.tip = J;
      pose.axis = ez;
      return pose;
    case KinematicsType::TableTableAC:
    case KinematicsType::TableTableBC: {
      const Eigen::Matrix3d R = table_rotation(k, j);
      const Eigen::Matrix3d Rt = rot(tilt_axis(k), tilt_of(j, k));
      const Eigen::Vector3d& r = machine_.pivot;
      const Eigen::Vector3d q = J - gauge_length_ * ez - r - (Eigen::Matrix3d::Identity() - Rt) * machine_.tilt_offset;
      pose.tip = R.transpose() * q + r;
      pose.axis = R.transpose() * ez;
      return pose;
    }
    case KinematicsType::HeadTableBC: {
      const Eigen::Matrix3d R = table_rotation(k, j);
      const Eigen::Vector3d u = machine_tool_axis(k, j);
      const Eigen::Vector3d q = J + machine_.head_pivot_length * ez - (gauge_length_ + machine_.head_pivot_length) * u;
      const Eigen::Vector3d& t = machine_.table_center;
      pose.tip = R.transpose() * (q - t) + t;
      pose.axis = R.transpose() * u;
      return pose;
    }
    case KinematicsType::HeadHeadAC: {
      const Eigen::Vector3d u = machine_tool_axis(k, j);
      pose.tip = J + machine_.head_pivot_length * ez - (gauge_length_ + machine_.head_pivot_length) * u;
      pose.axis = u;
      return pose;
    }
  }
  return pose;
}

namespace {

// X Y Z for the tip p at the rotary values already in j (the forward map's linear part inverted).
void solve_linear(const MachineSpec& m, double L, const Eigen::Vector3d& p, Joints& j) {
  const KinematicsType k = m.kinematics;
  const Eigen::Vector3d ez = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d J = p;
  if (is_table_table(k)) {
    const Eigen::Matrix3d Rt = rot(tilt_axis(k), tilt_of(j, k));
    J = table_rotation(k, j) * (p - m.pivot) + m.pivot + (Eigen::Matrix3d::Identity() - Rt) * m.tilt_offset + L * ez;
  } else if (k == KinematicsType::HeadTableBC) {
    const Eigen::Vector3d q = table_rotation(k, j) * (p - m.table_center) + m.table_center;
    J = q + (L + m.head_pivot_length) * machine_tool_axis(k, j) - m.head_pivot_length * ez;
  } else if (k == KinematicsType::HeadHeadAC) {
    J = p + (L + m.head_pivot_length) * machine_tool_axis(k, j) - m.head_pivot_length * ez;
  }
  j.x = J.x();
  j.y = J.y();
  j.z = J.z();
}

}  // namespace

bool Kinematics::within_limits(const Joints& j) const {
  for (const auto& [letter, lim] : machine_.limits) {
    const double v = letter == 'X' ? j.x : letter == 'Y' ? j.y : letter == 'Z' ? j.z : j.rotary(letter);
    if (!lim.contains(v)) return false;
  }
  return true;
}

std::vector<AxisOutside> axes_outside_limits(const MachineSpec& machine, const Joints& j, double slack) {
  std::vector<AxisOutside> out;
  for (int k = 0; k < 6; ++k) {
    const char axis = "XYZABC"[k];
    const auto it = machine.limits.find(axis);
    const double v = j.axis(k);
    if (it != machine.limits.end() && (v < it->second.min - slack || v > it->second.max + slack))
      out.push_back({axis, v, it->second});
  }
  return out;
}

std::optional<Joints> Kinematics::inverse_with_c(const ToolPose& pose, double c, const Joints& previous) const {
  const KinematicsType k = machine_.kinematics;
  if (k == KinematicsType::XYZ) return std::nullopt;
  const Eigen::Vector2d w = lean_direction(k, c);
  const double lean = w.x() * pose.axis.x() + w.y() * pose.axis.y();
  const double tilt = std::atan2(lean, pose.axis.z()) / kDeg;
  Joints j;
  j.c = c;
  const char t = tilt_letter(k);
  const double tv = unwind(tilt, tilt_of(previous, k), limit_of(machine_, t));
  if (std::isnan(tv) || !limit_of(machine_, 'C').contains(c)) return std::nullopt;
  set_tilt(j, k, tv);
  solve_linear(machine_, gauge_length_, pose.tip, j);
  if (!within_limits(j)) return std::nullopt;
  return j;
}

std::vector<Joints> Kinematics::inverse(const ToolPose& pose, const Joints& previous,
                                        const InverseOptions& options) const {
  std::vector<Joints> out;
  const KinematicsType k = machine_.kinematics;
  const Eigen::Vector3d axis = pose.axis.normalized();
  const double theta = pole_angle_deg(axis);
  if (k == KinematicsType::XYZ) {
    if (theta > options.pole_tolerance_deg) return out;
    Joints j;
    solve_linear(machine_, gauge_length_, pose.tip, j);
    if (within_limits(j)) out.push_back(j);
    return out;
  }
  const Eigen::Vector2d h(axis.x(), axis.y());
  const double hn = h.norm();
  if (theta < options.pole_tolerance_deg || hn < kPoleEpsilon) {
    // The pole: C is free, hold it (unwound toward the previous value within its limits).
    const double c = unwind(previous.c, previous.c, limit_of(machine_, 'C'));
    if (std::isnan(c)) return out;
    if (auto j = inverse_with_c(ToolPose{pose.tip, axis}, c, previous)) out.push_back(*j);
    return out;
  }
  const AxisLimit tl = limit_of(machine_, tilt_letter(k));
  const AxisLimit cl = limit_of(machine_, 'C');
  for (int sign : {1, -1}) {
    Joints j;
    const double c = unwind(c_of_lean(k, sign * h / hn), previous.c, cl);
    const double t = unwind(sign * theta, tilt_of(previous, k), tl);
    if (std::isnan(c) || std::isnan(t)) continue;
    j.c = c;
    set_tilt(j, k, t);
    solve_linear(machine_, gauge_length_, pose.tip, j);
    if (within_limits(j)) out.push_back(j);
  }
  return out;
}

std::optional<Joints> Kinematics::inverse_nearest(const ToolPose& pose, const Joints& previous,
                                                  const InverseOptions& options) const {
  const auto all = inverse(pose, previous, options);
  if (all.empty()) return std::nullopt;
  return *std::min_element(all.begin(), all.end(), [&](const Joints& a, const Joints& b) {
    return rotary_distance(a, previous) < rotary_distance(b, previous);
  });
}

Joints joints_for_tip(const std::function<ToolPose(const Joints&)>& forward, Joints at, const Eigen::Vector3d& tip) {
  at.x = at.y = at.z = 0.0;
  const Eigen::Vector3d t0 = forward(at).tip;
  Eigen::Matrix3d m;
  for (int k = 0; k < 3; ++k) {
    Joints e = at;
    (k == 0 ? e.x : k == 1 ? e.y : e.z) = 1.0;
    m.col(k) = forward(e).tip - t0;
  }
  const Eigen::Vector3d x = m.partialPivLu().solve(tip - t0);
  at.x = x.x();
  at.y = x.y();
  at.z = x.z();
  return at;
}

}  // namespace tf
