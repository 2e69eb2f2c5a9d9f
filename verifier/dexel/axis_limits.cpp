// The machine's axes against their limits at each block (Simulator::run): where a controller would stop.
#include "axis_limits.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <string_view>

#include "tiltfield/dexel/sweep.hpp"

namespace tf::sim {
namespace {

// The block's times where an arc's point reaches an extreme of its plane (the circle's quarter points it
// passes), then its end.
std::vector<double> times_to_check(const Block& b, const Joints& from) {
  std::vector<double> taus;
  if (b.motion == Motion::ArcCW || b.motion == Motion::ArcCCW) {
    const Joints mid = interpolate_block(from, b, 0.5);
    int iu = 0, iv = 1;
    if (b.plane == 18) iu = 2, iv = 0;
    if (b.plane == 19) iu = 1, iv = 2;
    const Eigen::Vector3d s(from.x, from.y, from.z), m(mid.x, mid.y, mid.z), c = b.arc_center;
    const double as = std::atan2(s[iv] - c[iv], s[iu] - c[iu]), am = std::atan2(m[iv] - c[iv], m[iu] - c[iu]);
    const double sign = b.motion == Motion::ArcCCW ? 1.0 : -1.0, two_pi = 2.0 * std::numbers::pi;
    // The sweep from the middle's angle (interpolate_block's own: a full circle or a short arc alike).
    const double half = std::fmod(sign * (am - as) + 2.0 * two_pi, two_pi);
    const double sweep = 2.0 * half;
    for (int q = 0; q < 4 && sweep > 0.0; ++q) {
      // Quarter angles ahead of the start along the motion: as + sign * d, d in (0, sweep).
      const double target = q * std::numbers::pi / 2.0;
      const double d = std::fmod(sign * (target - as) + 2.0 * two_pi, two_pi);
      if (d > 0.0 && d < sweep) taus.push_back(d / sweep);
    }
  }
  // Under TCP the machine's linear axes follow the pivots round while the rotaries turn: a swing can carry
  // them beyond a limit mid-block with both ends inside. Sampled every degree of the largest rotary turn
  // (a point 500 mm from a pivot is then missed by at most 0.02 mm).
  if (b.tcp) {
    const double turn = std::max({std::abs(b.target.a - from.a), std::abs(b.target.b - from.b), std::abs(b.target.c - from.c)});
    const int n = static_cast<int>(std::min(720.0, std::ceil(turn)));
    for (int k = 1; k < n; ++k) taus.push_back(double(k) / n);
  }
  taus.push_back(1.0);
  return taus;
}

}  // namespace

void check_axis_limits(const MachineSpec& machine, const Block& b, const Joints& from, int index,
                       const ForwardFn& forward, VerifyReport& rep, double nose_above_tip) {
  if (machine.limits.empty()) return;
  // Per axis the farthest it goes beyond its limit in the block.
  std::array<std::optional<AxisOutside>, 6> worst{};
  auto beyond = [](const AxisOutside& e) { return std::max(e.limit.min - e.value, e.value - e.limit.max); };
  for (const double tau : times_to_check(b, from)) {
    Joints j = interpolate_block(from, b, tau);
    if (b.tcp) {  // X Y Z are the tip in the part frame: the machine's come from the kinematics
      j = joints_for_tip(forward, j, Eigen::Vector3d(j.x, j.y, j.z));
    } else {
      j.z += nose_above_tip;
    }
    // A rounding's worth of slack: a program written to 4 decimals at the limit is within it.
    for (const AxisOutside& e : axes_outside_limits(machine, j, 1e-6)) {
      auto& w = worst[std::string_view("XYZABC").find(e.axis)];
      if (!w || beyond(e) > beyond(*w)) w = e;
    }
  }
  for (const auto& e : worst)
    if (e) rep.axis_limits.push_back({index, b.line, e->axis, e->value, e->limit.min, e->limit.max});
}

}  // namespace tf::sim
