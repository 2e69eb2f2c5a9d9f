// Choosing one joint solution per row: both solutions, limits, unwinding, the singular pole.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "post_internal.hpp"
#include "tiltfield/core/angles.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::post_detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double wrap180(double d) { return d - 360.0 * std::round(d / 360.0); }

bool tilt_is_a(KinematicsType k) { return k == KinematicsType::TableTableAC || k == KinematicsType::HeadHeadAC; }
char tilt_letter(KinematicsType k) { return tilt_is_a(k) ? 'A' : 'B'; }
void set_tilt(Joints& j, KinematicsType k, double v) { (tilt_is_a(k) ? j.a : j.b) = v; }

const AxisLimit* limit(const MachineSpec& m, char letter) {
  auto it = m.limits.find(letter);
  return it == m.limits.end() ? nullptr : &it->second;
}

struct Candidate {
  double tilt, c;
};

// Rotary distance of two candidates; continuous axes count the short way round.
struct RotaryMetric {
  bool tilt_continuous, c_continuous;
  double tilt(double a, double b) const { return std::abs(tilt_continuous ? wrap180(a - b) : a - b); }
  double c(double a, double b) const { return std::abs(c_continuous ? wrap180(a - b) : a - b); }
};

bool is_pole(const ToolPose& pose, double pole_tolerance_deg) {
  return Kinematics::pole_angle_deg(pose.axis) < pole_tolerance_deg || std::hypot(pose.axis.x(), pose.axis.y()) < 1e-12;
}

// The values v + 360 k inside `limit`, however far from 0 it lies: at most kMaxTurns of them, those nearest
// to v (a limit of many turns offers more than the dynamic programme needs). A value within kLimitSnap of
// a limit is the limit, as in core's unwinding: C computed as 179.99999999999997 on C [-180, 180] offers
// -180 too (its turn had been dropped as -180.00000000000003, and the post unwound a whole turn).
constexpr int kMaxTurns = 16;
constexpr double kLimitSnap = 1e-6;  // deg
std::vector<double> turns_within(double v, const AxisLimit& limit) {
  const double k_lo = std::ceil((limit.min - kLimitSnap - v) / 360.0), k_hi = std::floor((limit.max + kLimitSnap - v) / 360.0);
  std::vector<double> out;
  if (!(k_lo <= k_hi)) return out;
  const double first = std::max(k_lo, std::min(k_hi, 0.0) - kMaxTurns / 2), last = std::min(k_hi, first + kMaxTurns - 1);
  for (double k = first; k <= last; ++k) out.push_back(std::clamp(v + 360.0 * k, limit.min, limit.max));
  return out;
}

// The candidates of a non-pole row: both solutions, and for a C axis with limits every turn inside them.
std::vector<Candidate> candidates(const ToolPose& pose, const Kinematics& kin, const AxisLimit* c_limit) {
  std::vector<Candidate> out;
  const KinematicsType k = kin.machine().kinematics;
  InverseOptions exact;
  exact.pole_tolerance_deg = 0.0;
  for (const Joints& j : kin.inverse(pose, Joints{}, exact)) {
    if (!c_limit) {
      out.push_back({tilt_of(j, k), wrap180(j.c)});
      continue;
    }
    for (const double c : turns_within(j.c, *c_limit)) out.push_back({tilt_of(j, k), c});
  }
  return out;
}

// A change between the two solutions across one move makes the tilt pass 0, so the joint-linear axis
// passes the pole itself and leaves the wanted arc by about the arc's distance from the pole: fine where
// the linearisation accepts that (inside the pole cone, or within the axis tolerance), otherwise the move
// cannot be linearised and would need a retract. Priced like one, so that it is taken only when forced.
constexpr double kFlipPenalty = 1e6;
bool flip_follows_the_arc(double arc_pole_deg, const PostOptions& options) {
  return arc_pole_deg < options.pole_tolerance_deg || arc_pole_deg < kLinearizeSafety * options.axis_tolerance_deg;
}

// The 3-axis machine: the tip alone, within the pole tolerance of a vertical axis.
std::vector<Joints> xyz_joints(const std::vector<ToolPose>& poses, const Kinematics& kin, const PostOptions& options) {
  std::vector<Joints> out(poses.size());
  InverseOptions io;
  io.pole_tolerance_deg = options.pole_tolerance_deg;
  for (size_t i = 0; i < poses.size(); ++i) {
    auto j = kin.inverse_nearest(poses[i], Joints{}, io);
    if (!j) throw PostRowError(i, unreachable_reason(poses[i], kin, options));
    out[i] = *j;
  }
  return out;
}

// Dynamic programming over the non-pole rows (the layers). cost[l][s]: least rotary motion up to layer l
// ending in candidate s; from[l][s]: the candidate of layer l - 1 it came from.
struct Layers {
  std::vector<size_t> row;
  std::vector<std::vector<Candidate>> cand;
  std::vector<std::vector<double>> cost;
  std::vector<std::vector<int>> from;
};

// The least cost (lc) of reaching each candidate c of row i from the last layer, and from where (lf).
void step_costs(const Layers& layers, const std::vector<ToolPose>& poses, size_t i, const std::vector<Candidate>& c,
                const RotaryMetric& metric, const PostOptions& options, std::vector<double>& lc, std::vector<int>& lf) {
  const bool through_pole = layers.row.back() + 1 != i;
  const bool flip_is_costly =
      !through_pole && !flip_follows_the_arc(arc_pole_distance(poses[i - 1].axis, poses[i].axis), options);
  const auto& pc = layers.cand.back();
  const auto& pcost = layers.cost.back();
  for (size_t s = 0; s < c.size(); ++s) {
    for (size_t p = 0; p < pc.size(); ++p) {
      const double dt = through_pole ? metric.tilt(pc[p].tilt, 0) + metric.tilt(0, c[s].tilt)
                                     : metric.tilt(pc[p].tilt, c[s].tilt);
      double v = pcost[p] + dt + metric.c(pc[p].c, c[s].c);
      // A limited C moving more than half a turn between neighbouring rows unwinds a turn: the joints
      // cannot follow the wanted axis there either, and the post changes configuration with a retract.
      // Priced as the costly flip is, once per move (one retract is one, found in review: a spiral took
      // two unwinds where one flip would do).
      const bool flip = flip_is_costly && (wrap180(pc[p].tilt) > 0) != (wrap180(c[s].tilt) > 0);
      const bool unwinds = !metric.c_continuous && metric.c(pc[p].c, c[s].c) > 180.0 + 1e-6;
      if (!through_pole && (flip || unwinds)) v += kFlipPenalty;
      if (v < lc[s]) {
        lc[s] = v;
        lf[s] = static_cast<int>(p);
      }
    }
  }
}

Layers solve_layers(const std::vector<ToolPose>& poses, const Kinematics& kin, const PostOptions& options,
                    const AxisLimit* c_limit, const RotaryMetric& metric) {
  Layers layers;
  for (size_t i = 0; i < poses.size(); ++i) {
    if (is_pole(poses[i], options.pole_tolerance_deg)) continue;
    auto c = candidates(poses[i], kin, c_limit);
    if (c.empty()) throw PostRowError(i, unreachable_reason(poses[i], kin, options));
    std::vector<double> lc(c.size(), kInf);
    std::vector<int> lf(c.size(), -1);
    if (layers.row.empty()) {
      // Start near the rotaries' zero; the small weight only breaks ties.
      for (size_t s = 0; s < c.size(); ++s) lc[s] = 1e-3 * (metric.tilt(c[s].tilt, 0) + metric.c(c[s].c, 0));
    } else {
      step_costs(layers, poses, i, c, metric, options, lc, lf);
    }
    layers.row.push_back(i);
    layers.cand.push_back(std::move(c));
    layers.cost.push_back(std::move(lc));
    layers.from.push_back(std::move(lf));
  }
  return layers;
}

// Back-tracks the cheapest candidate of every layer, then unwinds continuous axes along the path.
std::vector<Candidate> cheapest_candidates(const Layers& layers, const RotaryMetric& metric) {
  std::vector<Candidate> chosen(layers.row.size());
  if (layers.row.empty()) return chosen;
  const auto& last = layers.cost.back();
  int s = static_cast<int>(std::min_element(last.begin(), last.end()) - last.begin());
  for (size_t l = layers.row.size(); l-- > 0;) {
    chosen[l] = layers.cand[l][s];
    s = layers.from[l][s];
  }
  for (size_t l = 1; l < chosen.size(); ++l) {
    if (metric.c_continuous) chosen[l].c = chosen[l - 1].c + wrap180(chosen[l].c - chosen[l - 1].c);
    if (metric.tilt_continuous) chosen[l].tilt = chosen[l - 1].tilt + wrap180(chosen[l].tilt - chosen[l - 1].tilt);
  }
  return chosen;
}

// C of every run of pole rows: held from the neighbours, or (PoleMode::Interpolate, between two of them)
// interpolated along the tip path. A path wholly in the cone takes C at its rest: 0, or the value nearest
// 0 that C's limits allow (any C reaches the pole; 0 was refused on a table whose C runs 100..460).
void fill_pole_runs(const std::vector<ToolPose>& poses, const std::vector<char>& pole, const PostOptions& options,
                    const AxisLimit* c_limit, std::vector<double>& c_of) {
  const double c_rest = c_limit ? std::clamp(0.0, c_limit->min, c_limit->max) : 0.0;
  const size_t n = poses.size();
  size_t i = 0;
  while (i < n) {
    if (!pole[i]) {
      ++i;
      continue;
    }
    size_t e = i;
    while (e + 1 < n && pole[e + 1]) ++e;
    const bool has_before = i > 0, has_after = e + 1 < n;
    const double c0 = has_before ? c_of[i - 1] : has_after ? c_of[e + 1] : c_rest;
    const double c1 = has_after ? c_of[e + 1] : c0;
    // Path length along the tips from the row before the run to the row after it.
    const size_t a = has_before ? i - 1 : i, b = has_after ? e + 1 : e;
    std::vector<double> len(b - a + 1, 0.0);
    for (size_t r = a + 1; r <= b; ++r) len[r - a] = len[r - a - 1] + (poses[r].tip - poses[r - 1].tip).norm();
    for (size_t r = i; r <= e; ++r) {
      double w = 0.0;
      if (options.pole_mode == PoleMode::Interpolate && has_before && has_after)
        w = len.back() > 1e-12 ? len[r - a] / len.back() : double(r - a) / double(b - a);
      c_of[r] = c0 + (c1 - c0) * w;
    }
    i = e + 1;
  }
}

// The joints of every row at its C, each seeded by the previous row's and (off the pole) the chosen tilt.
std::vector<Joints> joints_at_c(const std::vector<ToolPose>& poses, const Kinematics& kin, const PostOptions& options,
                                const std::vector<double>& c_of, const std::vector<double>& tilt_hint,
                                const std::vector<char>& pole) {
  const KinematicsType k = kin.machine().kinematics;
  std::vector<Joints> out(poses.size());
  Joints prev;
  for (size_t r = 0; r < poses.size(); ++r) {
    Joints hint = prev;
    if (!pole[r]) set_tilt(hint, k, tilt_hint[r]);
    auto j = kin.inverse_with_c(poses[r], c_of[r], hint);
    if (!j) throw PostRowError(r, unreachable_reason(poses[r], kin, options));
    out[r] = *j;
    prev = *j;
  }
  return out;
}

}  // namespace

double arc_pole_distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double ends = std::min(Kinematics::pole_angle_deg(a), Kinematics::pole_angle_deg(b));
  const Eigen::Vector3d n = a.cross(b);
  if (n.norm() < 1e-12) return ends;
  const Eigen::Vector3d u = n.normalized();
  const Eigen::Vector3d w = Eigen::Vector3d(-u.z() * u.x(), -u.z() * u.y(), 1.0 - u.z() * u.z());  // ez off the plane
  if (w.norm() < 1e-12) return ends;                                                             // arc on the equator
  const Eigen::Vector3d wn = w.normalized();
  auto ang = [](const Eigen::Vector3d& x, const Eigen::Vector3d& y) { return angle_between(x, y); };
  if (std::abs(ang(a, wn) + ang(wn, b) - ang(a, b)) > 1e-9) return ends;  // the nearest point is off the arc
  return std::asin(std::min(1.0, std::abs(u.z()))) * 180.0 / 3.14159265358979323846;
}

std::vector<Joints> all_solutions(const ToolPose& pose, const Kinematics& kin, const Joints& near) {
  InverseOptions exact;
  exact.pole_tolerance_deg = 0.0;
  std::vector<Joints> out;
  const AxisLimit* c_limit = limit(kin.machine(), 'C');
  for (const Joints& j : kin.inverse(pose, near, exact)) {
    if (!c_limit) {
      out.push_back(j);
      continue;
    }
    for (const double c : turns_within(j.c, *c_limit))
      if (auto t = kin.inverse_with_c(pose, c, j)) out.push_back(*t);
  }
  return out;
}

std::string unreachable_reason(const ToolPose& pose, const Kinematics& kin, const PostOptions& options) {
  const MachineSpec& m = kin.machine();
  const double theta = Kinematics::pole_angle_deg(pose.axis);
  std::ostringstream s;
  s << "tool axis (" << fixed(pose.axis.x(), 6) << ", " << fixed(pose.axis.y(), 6) << ", " << fixed(pose.axis.z(), 6)
    << ") at tip (" << fixed(pose.tip.x(), 4) << ", " << fixed(pose.tip.y(), 4) << ", " << fixed(pose.tip.z(), 4) << ")";
  if (m.kinematics == KinematicsType::XYZ) {
    s << " is " << fixed(theta, 4) << " deg from +Z; the 3-axis machine allows " << fixed(options.pole_tolerance_deg, 4)
      << " deg (--pole-tol)";
    return "unreachable pose: " + s.str();
  }
  const char t = tilt_letter(m.kinematics);
  if (const AxisLimit* tl = limit(m, t)) {
    auto fits = [&](double v) {
      for (int turn = -1; turn <= 1; ++turn)
        if (tl->contains(v + 360.0 * turn)) return true;
      return false;
    };
    if (!fits(theta) && !fits(-theta)) {
      // Within a digit of a limit, as many digits as show it outside (black-box testing: "needs A = +-100"
      // for limits [-100, 50] was -100.000005).
      const bool near_limit = std::abs(theta - std::abs(tl->min)) < 1e-4 || std::abs(theta - std::abs(tl->max)) < 1e-4;
      s << " needs " << t << " = +-" << fixed(theta, near_limit ? 8 : 4) << " deg, outside the " << t << " limits [" << fixed(tl->min, 4)
        << ", " << fixed(tl->max, 4) << "]";
      return "unreachable pose: " + s.str();
    }
  }
  // The rotaries fit: some other limit (C's turns, X, Y or Z) rules both solutions out.
  MachineSpec free = m;
  free.limits.clear();
  const Kinematics unlimited(free, kin.gauge_length());
  InverseOptions exact;
  exact.pole_tolerance_deg = 0.0;
  s << ":";
  bool first = true;
  for (const Joints& j : unlimited.inverse(pose, Joints{}, exact)) {
    s << (first ? "" : ";") << " solution " << t << "=" << fixed(tilt_of(j, m.kinematics), 3) << " C=" << fixed(j.c, 3);
    first = false;
    for (const auto& [letter, lim] : m.limits) {
      double v = letter == 'X' ? j.x : letter == 'Y' ? j.y : letter == 'Z' ? j.z : j.rotary(letter);
      if (letter == 'C' || letter == t) {
        if (!turns_within(v, lim).empty()) continue;
      } else if (lim.contains(v)) {
        continue;
      }
      s << " has " << letter << " " << fixed(v, 3) << " outside [" << fixed(lim.min, 3) << ", " << fixed(lim.max, 3) << "]";
    }
  }
  return "unreachable pose: " + s.str();
}

std::vector<Joints> choose_joints(const std::vector<ToolPose>& poses, const Kinematics& kin, const PostOptions& options) {
  const MachineSpec& m = kin.machine();
  const KinematicsType k = m.kinematics;
  if (k == KinematicsType::XYZ) return xyz_joints(poses, kin, options);
  const AxisLimit* c_limit = limit(m, 'C');
  const RotaryMetric metric{limit(m, tilt_letter(k)) == nullptr, c_limit == nullptr};
  const Layers layers = solve_layers(poses, kin, options, c_limit, metric);
  const std::vector<Candidate> chosen = cheapest_candidates(layers, metric);

  // C of every row: the chosen one, or for pole rows held / interpolated between the neighbours.
  const size_t n = poses.size();
  std::vector<double> c_of(n, 0.0), tilt_hint(n, 0.0);
  std::vector<char> pole(n, 1);
  for (size_t l = 0; l < layers.row.size(); ++l) {
    c_of[layers.row[l]] = chosen[l].c;
    tilt_hint[layers.row[l]] = chosen[l].tilt;
    pole[layers.row[l]] = 0;
  }
  fill_pole_runs(poses, pole, options, c_limit, c_of);
  return joints_at_c(poses, kin, options, c_of, tilt_hint, pole);
}

}  // namespace tf::post_detail
