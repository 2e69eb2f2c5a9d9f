// The program builder's moves: start, finish, links, changes of configuration, cutting blocks and the
// retracts and transit heights they go through.
#include "program_builder.hpp"

#include <algorithm>
#include <cmath>

#include "tiltfield/core/error.hpp"

namespace tf::post_detail {

void Builder::start(const ToolPose& pose, const Joints& j, double feed) {
  const Transit t = transit(pose, j);
  prog_.start = t.high;
  prog_.start.a = prog_.start.b = prog_.start.c = 0.0;
  check_lowered_turn(prog_.start, t.high, t.high);
  rapid(prog_.start);  // written as Z alone: the other axes' positions are not known yet
  rapid(prog_.start);  // over the first point with the rotaries at 0, so that the turn is made where checked
  rapid(t.high);
  if (t.via) rapid(*t.via);
  rapid(t.retract);
  plunge(target(pose, j), feed);
}

void Builder::link(const ToolPose& from_pose, const Joints& from, const ToolPose& to_pose, const Joints& to, double feed) {
  const bool same_rotaries =
      std::abs(from.a - to.a) < 1e-9 && std::abs(from.b - to.b) < 1e-9 && std::abs(from.c - to.c) < 1e-9;
  if (!same_rotaries || !check_.active()) {
    reposition(from_pose, from, to_pose, to, feed);
    return;
  }
  const Transit a = transit(from_pose, from, false), b = transit(to_pose, to, false);
  const std::optional<double> h = link_height(a.retract, b.retract, from_pose.axis);
  if (!h) {
    reposition(from_pose, from, to_pose, to, feed);
    return;
  }
  Joints over_a = a.retract, over_b = b.retract;
  over_a.z = over_b.z = *h;
  rapid(a.retract);
  if (over_a.z > a.retract.z) rapid(over_a);
  rapid(over_b);
  if (over_b.z > b.retract.z) rapid(b.retract);
  plunge(target(to_pose, to), feed);
}

void Builder::reposition(const ToolPose& from_pose, const Joints& from, const ToolPose& to_pose, const Joints& to, double feed) {
  const Transit a = transit(from_pose, from), b = transit(to_pose, to);
  rapid(a.retract);
  if (a.via) rapid(*a.via);
  rapid(a.high);
  Joints turned = a.high;
  turned.a = b.high.a;
  turned.b = b.high.b;
  turned.c = b.high.c;
  check_turn(a.high, turned);
  check_lowered_turn(a.high, turned, b.high);
  rapid(turned);
  rapid(b.high);
  if (b.via) rapid(*b.via);
  rapid(b.retract);
  plunge(target(to_pose, to), feed);
}

void Builder::cut(const ToolPose& p0, const Joints& j0, const ToolPose& p1, const Joints& j1, double feed) {
  feed = std::min(feed, job_.machine.max_feed);
  const double d_tip = (p1.tip - p0.tip).norm();
  const double d_rot = std::max({std::abs(j1.a - j0.a), std::abs(j1.b - j0.b), std::abs(j1.c - j0.c)});
  const double d_xyz = Eigen::Vector3d(j1.x - j0.x, j1.y - j0.y, j1.z - j0.z).norm();
  if (d_tip < 1e-9 && d_rot < 1e-9 && d_xyz < 1e-9) return;  // a repeated row
  Block b = block(Motion::Linear, target(p1, j1));
  if (tcp_ || d_rot < 1e-9) {
    b.feed_mode = FeedMode::PerMinute;
    b.feed = feed;
    // Under TCP, F is the tip's speed and the controller moves the axes to keep it: a turn about a tip
    // that moves little had asked C for 44 000 deg/min of a machine's 1 800 (black-box testing). The tip
    // slows so that no axis exceeds its top speed, timed from the ends as written; where the written tip
    // does not move, F is read as degrees a minute (a rotary-only move), and the linear axes, following
    // the part round, still keep theirs.
    if (tcp_) {  // the rotaries as written may turn where the rows' barely do
      const Joints w0 = written(target(p0, j0)), w1 = written(target(p1, j1));
      const double tip = Eigen::Vector3d(w1.x - w0.x, w1.y - w0.y, w1.z - w0.z).norm();
      const double rot = std::max({std::abs(w1.a - w0.a), std::abs(w1.b - w0.b), std::abs(w1.c - w0.c)});
      const double linear = tcp_linear_path(w0, w1);
      double capped = feed;
      if (tip == 0.0) {
        capped = std::min(feed, job_.machine.max_rotary_feed);
        if (linear > 0.0) capped = std::min(capped, job_.machine.max_feed * rot / linear);
      } else {
        const double axes = std::max(linear / job_.machine.max_feed, rot / job_.machine.max_rotary_feed);
        if (tip / feed < axes * (1.0 - 1e-9)) capped = tip / axes;  // not where the tip alone sets the time
      }
      // Rounded down to the 2 decimals written (gcode_writer rounds to nearest), where that leaves any.
      if (capped < feed) b.feed = std::floor(capped * 100.0) >= 1.0 ? std::floor(capped * 100.0) / 100.0 : capped;
    }
  } else {
    // Inverse time: the tip at the feed, unless an axis would exceed its top speed. The controller times
    // the axes' moves as written, each end rounded (kAxisDecimals): a block of 0.0002 mm could read 50 %
    // longer, and its F had driven X 58 % over max_feed (found by black-box testing).
    // The tip too moves as written: on a block of 3.6 um near the pole the rounded ends had read 1 % faster.
    const double tip_written = (kin_.forward(written(target(p1, j1))).tip - kin_.forward(written(target(p0, j0))).tip).norm();
    const double minutes = std::max({std::max(d_tip, tip_written) / feed,
                                     (d_xyz + std::sqrt(3.0) * kAxisUnit) / job_.machine.max_feed,
                                     (d_rot + kAxisUnit) / job_.machine.max_rotary_feed});
    b.feed_mode = FeedMode::InverseTime;
    b.feed = 1.0 / minutes;
  }
  prog_.blocks.push_back(b);
}

double Builder::tcp_linear_path(const Joints& from, const Joints& to) const {
  // The controller interpolates the tip and the rotaries linearly; the linear axes follow the part round
  // on arcs, so the chord of their ends undercounts their speed (by 11 % over a quarter turn). Sampled
  // every degree of the largest rotary turn, the longest piece times the pieces is the peak speed over
  // the block's time, in mm per block.
  const double turn = std::max({std::abs(to.a - from.a), std::abs(to.b - from.b), std::abs(to.c - from.c)});
  const int n = std::max(1, static_cast<int>(std::min(720.0, std::ceil(turn))));
  const auto at = [&](double s) {
    Joints q = from;
    for (int k = 0; k < 6; ++k) q.axis(k) += s * (to.axis(k) - from.axis(k));
    const Joints m = machine_joints(q);
    return Eigen::Vector3d(m.x, m.y, m.z);
  };
  Eigen::Vector3d prev = at(0.0);
  double longest = 0.0;
  for (int k = 1; k <= n; ++k) {
    const Eigen::Vector3d next = at(double(k) / n);
    longest = std::max(longest, (next - prev).norm());
    prev = next;
  }
  return longest * n;
}

Joints Builder::written(const Joints& j) const {
  Joints w = j;
  for (int k = 0; k < 6; ++k) w.axis(k) = as_written(j.axis(k), job_.work_offset[size_t(k)]);
  return w;
}

Joints Builder::target(const ToolPose& pose, const Joints& j) const {
  Joints t = j;
  if (!tcp_) {
    // The rotaries as written, and X Y Z that put the tip where it belongs at them: on a head pivot of
    // 10 m half of the last decimal had moved the tip 0.009 mm (black-box testing).
    const auto& off = job_.work_offset;
    t.a = as_written(j.a, off[3]);
    t.b = as_written(j.b, off[4]);
    t.c = as_written(j.c, off[5]);
    return joints_for_tip([this](const Joints& q) { return kin_.forward(q); }, t, pose.tip);
  }
  t.x = pose.tip.x();
  t.y = pose.tip.y();
  t.z = pose.tip.z();
  return t;
}

void Builder::check_turn(const Joints& from, const Joints& to) const {
  if (!tcp_) return;
  const double turn = std::max({std::abs(to.a - from.a), std::abs(to.b - from.b), std::abs(to.c - from.c)});
  const int n = std::max(1, static_cast<int>(std::min(720.0, std::ceil(turn))));
  for (int k = 0; k <= n; ++k) {
    Joints j = from;
    const double s = double(k) / n;
    j.a += s * (to.a - from.a), j.b += s * (to.b - from.b), j.c += s * (to.c - from.c);
    if (!machine_within(j))
      throw JobError("turning the rotaries at the transit point X " + fixed(from.x, 3) + " Y " + fixed(from.y, 3) + " Z " +
                     fixed(from.z, 3) + " under tool-centre-point control takes the machine outside its limits (" +
                     outside_limits(machine_joints(j)) + ")");
  }
}

void Builder::check_lowered_turn(const Joints& from, const Joints& turned, const Joints& over) const {
  if (!clearing_height_ || !check_.active()) return;
  const double margin = 0.5 * job_.machine.safe_z;
  // The body turns by at most the sum of the rotaries' turns (the largest alone falls short when two turn).
  const double turn_deg = std::abs(turned.a - from.a) + std::abs(turned.b - from.b) + std::abs(turned.c - from.c);
  const auto pose_at = [&](double s) {
    Joints j = from;
    j.a += s * (turned.a - from.a), j.b += s * (turned.b - from.b), j.c += s * (turned.c - from.c);
    return kin_.forward(j);
  };
  const ToolPose at_turned = kin_.forward(turned);
  const bool turn_ok = check_.turn_clear(pose_at, turn_deg * M_PI / 180.0, margin);
  if (turn_ok && check_.translation_clear(at_turned, kin_.forward(over).tip - at_turned.tip, margin)) return;
  std::string turn = "A " + fixed(from.a, 3) + " B " + fixed(from.b, 3) + " C " + fixed(from.c, 3) + " to A " +
                     fixed(turned.a, 3) + " B " + fixed(turned.b, 3) + " C " + fixed(turned.c, 3);
  throw JobError("the transit height is lowered to Z's limit " + fixed(zsafe_, 3) + " (every turn of the rotaries clears at Z " +
                 fixed(*clearing_height_, 3) + "): " + (turn_ok ? "the move after turning " : "turning ") + turn +
                 " at X " + fixed(from.x, 3) + " Y " + fixed(from.y, 3) + " comes within " + fixed(margin, 3) +
                 " mm (half of safe_z) of the stock, fixtures or check surfaces; raise Z's limit in the machine file");
}

bool Builder::rapids_clear(const std::vector<Joints>& corners, const Eigen::Vector3d& axis) const {
  const double margin = 0.5 * job_.machine.safe_z;
  for (size_t k = 0; k < corners.size(); ++k) {
    if (!machine_within(corners[k])) return false;
    if (k == 0) continue;
    const ToolPose p0 = pose_at(corners[k - 1], axis), p1 = pose_at(corners[k], axis);
    if (!check_.translation_clear(p0, p1.tip - p0.tip, margin)) return false;
  }
  return true;
}

std::optional<double> Builder::link_height(const Joints& a, const Joints& b, const Eigen::Vector3d& axis) const {
  const double lo = std::max(a.z, b.z), hi = std::max(lo, zsafe_);
  auto clears_at = [&](double z) {
    Joints up_a = a, up_b = b;
    up_a.z = up_b.z = z;
    return rapids_clear({a, up_a, up_b, b}, axis);
  };
  constexpr int kSteps = 16;
  for (int k = 0; k <= kSteps; ++k) {
    double good = lo + (hi - lo) * k / kSteps;
    if (!clears_at(good)) continue;
    if (k == 0) return good;
    double bad = lo + (hi - lo) * (k - 1) / kSteps;
    for (int i = 0; i < 8; ++i) {
      const double mid = 0.5 * (bad + good);
      (clears_at(mid) ? good : bad) = mid;
    }
    return good;
  }
  return std::nullopt;
}

double Builder::transit_height() const {
  const MachineSpec& m = job_.machine;
  const double top = bounds_.max().z() + m.safe_z;
  if (tcp_) return top;
  const double L = kin_.gauge_length();
  if (m.kinematics == KinematicsType::XYZ) return top;
  if (m.kinematics == KinematicsType::TableTableAC || m.kinematics == KinematicsType::TableTableBC) {
    // Any turn of the table keeps the part inside the sphere about the pivot that holds its bounds.
    const double reach = (bounds_.center() - m.pivot).norm() + 0.5 * bounds_.sizes().norm() + 2.0 * m.tilt_offset.norm();
    return m.pivot.z() + reach + m.safe_z + L;
  }
  return top + L;  // head machines: a vertical tool is the lowest; joint Z = tip Z + L there
}

Builder::Transit Builder::transit(const ToolPose& pose, const Joints& j, bool check_rise) {
  const double full = full_lift(pose);
  if (!check_.active()) return reachable(transit_at(pose, j, full, full));
  const double lift = check_.lowest_lift(pose, std::min(1.0, full), full, job_.machine.safe_z).value_or(full);
  Transit t = transit_at(pose, j, lift, full);
  if (!check_rise) return t;  // only the retract is used
  if (lift >= full) return reachable(t);
  // A rise along the axis that goes sideways farther than the full retract would (by more than safe_z)
  // is not needed: the full retract's vertical rise clears. Along an axis 84 deg off vertical on a head
  // machine without X or Y limits it had gone 2.2 m sideways to reach the transit height (black-box
  // testing; the limits had stopped it where they exist). A table's tool stays vertical: never sideways.
  const ToolPose low = pose_at(t.retract, pose.axis), high = pose_at(t.high, pose.axis);
  if (t.high_within_limits && t.sideways_beyond_full <= job_.machine.safe_z &&
      check_.translation_clear(low, high.tip - low.tip, 0.5 * job_.machine.safe_z))
    return t;
  Transit f = reachable(transit_at(pose, j, full, full));
  // Out along the axis to the full retract by rapid, the plunge from the shorter one: the full lift at
  // half the feed had cost seconds a link.
  const ToolPose out = pose_at(f.retract, pose.axis);
  if (t.high_within_limits && t.sideways_beyond_full > job_.machine.safe_z &&
      check_.translation_clear(low, out.tip - low.tip, 0.5 * job_.machine.safe_z)) {
    f.via = f.retract;
    f.retract = t.retract;
  }
  return f;
}

Builder::Transit Builder::reachable(Transit t) const {
  if (!t.high_within_limits)
    throw JobError("the transit point X " + fixed(t.high.x, 3) + " Y " + fixed(t.high.y, 3) + " Z " + fixed(t.high.z, 3) +
                   " over a retract is outside the machine's limits (" + outside_limits(machine_joints(t.high)) + ")" +
                   (tcp_ ? "; under tool-centre-point control the transit height is the part's top + safe_z, which the "
                           "machine must reach at every retract's rotaries (the joint dialect caps it at Z's limit)"
                         : ""));
  return t;
}

Builder::Transit Builder::transit_at(const ToolPose& pose, const Joints& j, double lift, double full) {
  const double wanted = lift;  // the limits may shorten it
  Transit t;
  // The retract `l` along the axis, programmed; nullopt where the machine's limits do not reach it.
  auto retract_at = [&](double l) -> std::optional<Joints> {
    const ToolPose p{pose.tip + l * pose.axis, pose.axis};
    if (!tcp_) return joints_at_rotaries(kin_, p, j);
    const Joints r = target(p, j);
    return machine_within(r) ? std::optional<Joints>(r) : std::nullopt;
  };
  // Back off along the axis; where the full lift leaves the limits, as far as they allow.
  std::optional<Joints> r = retract_at(lift);
  for (int tries = 1; tries < 8 && !r; ++tries) {
    lift *= 0.5;
    r = retract_at(lift);
  }
  if (!r) throw JobError("no retract along the tool axis stays within the machine's limits");
  if (tries_warned_ == 0 && lift < std::min(wanted, job_.machine.safe_z) - 1e-9) {
    prog_.warnings.push_back("a retract is shortened to " + fixed(lift, 3) + " mm by the machine's limits");
    ++tries_warned_;
  }
  t.retract = *r;
  // How the programmed XYZ move when the tip moves along its axis: the axis itself under TCP.
  const Eigen::Vector3d dir =
      tcp_ ? pose.axis : Eigen::Vector3d(r->x - j.x, r->y - j.y, r->z - j.z).normalized();
  t.high = t.retract;
  const double z = std::max(zsafe_, t.retract.z);  // zsafe_ is within Z's limits, retract too
  const bool straight_up = lift >= full - 1e-9 && pose.axis.z() >= 0.0;
  if (!straight_up && dir.z() > 0.05) {
    const double k = (z - t.retract.z) / dir.z();
    t.high.x += k * dir.x();
    t.high.y += k * dir.y();
    t.sideways_beyond_full = std::max(0.0, lift + k - full) * std::hypot(dir.x(), dir.y());
  }
  t.high.z = z;
  t.high_within_limits = machine_within(t.high);
  return t;
}

std::string Builder::outside_limits(const Joints& j) const {
  std::string out;
  for (const AxisOutside& e : axes_outside_limits(job_.machine, j))
    out += (out.empty() ? "" : ", ") + std::string(1, e.axis) + " " + fixed(e.value, 3) +
           (e.value > e.limit.max ? " > " + fixed(e.limit.max, 3) : " < " + fixed(e.limit.min, 3));
  return out;
}

Block Builder::block(Motion motion, const Joints& target) const {
  Block b;
  b.motion = motion;
  b.target = target;
  b.tcp = tcp_;
  b.spindle_rpm = opt_.spindle_rpm;
  b.tool = opt_.tool_number;
  return b;
}

void Builder::plunge(const Joints& to, double feed) {
  Block b = block(Motion::Linear, to);
  b.feed_mode = FeedMode::PerMinute;
  b.feed = std::min(feed, job_.machine.max_feed) * opt_.plunge_feed_fraction;
  prog_.blocks.push_back(b);
}

}  // namespace tf::post_detail
