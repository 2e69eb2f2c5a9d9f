// The post-processor's main loop: rows -> tool poses -> joints -> linearised blocks, with the safe
// approach, retract, links between rows too far apart to cut through and (where the limits force one)
// change of configuration.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "post_internal.hpp"
#include "transit_check.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/local_frame.hpp"

namespace tf {
using namespace post_detail;

Dialect effective_dialect(const PostOptions& options, const MachineSpec& machine) {
  if (options.dialect) return *options.dialect;
  return machine.output == OutputMode::Tcp ? Dialect::Tcp : Dialect::Joint;
}

double effective_link_gap(const PostOptions& options, const Tool& tool) {
  return options.link_gap_mm.value_or(default_link_gap(tool));
}

void set_transit_obstacles(PostJob& job, const Scene& scene) {
  job.stock = stock_to_mesh(scene.stock);
  job.fixtures.clear();
  job.check_surfaces.clear();
  for (const Mesh& m : scene.fixtures) job.fixtures.push_back(&m);
  for (const Mesh& m : scene.check_surfaces) job.check_surfaces.push_back(&m);
}

void set_post_job(PostJob& job, const Scene& scene, int tool_number) {
  job.machine = scene.machine.value_or(MachineSpec{});
  job.tool = scene.tool;
  if (!scene.tools.empty()) {
    const auto it = std::find_if(scene.tools.begin(), scene.tools.end(),
                                 [&](const ToolEntry& e) { return e.number == tool_number; });
    if (it == scene.tools.end()) {
      std::string numbers;
      for (const ToolEntry& e : scene.tools) numbers += (numbers.empty() ? "" : ", ") + std::to_string(e.number);
      throw InputError("", 0, "--tool-number",
                       "tool " + std::to_string(tool_number) + " is not in the scene's tool library (" + numbers + ")");
    }
    job.tool = it->tool;
  }
  job.feed = scene.feed;
  job.part_bounds = scene_bounds(scene);
  set_transit_obstacles(job, scene);
  const auto g54 = scene.work_offsets.find("G54");
  job.work_offset = g54 == scene.work_offsets.end() ? WorkOffset{} : g54->second;
}

namespace {

class Builder {
 public:
  Builder(const Kinematics& kin, const PostJob& job, const PostOptions& opt, bool tcp, Eigen::AlignedBox3d bounds,
          const TransitChecker& check)
      : kin_(kin), job_(job), opt_(opt), tcp_(tcp), bounds_(bounds), check_(check) {
    zsafe_ = transit_height();
    const auto zl = job.machine.limits.find('Z');
    if (!tcp_ && zl != job.machine.limits.end() && zsafe_ > zl->second.max) {
      prog_.warnings.push_back("the transit height Z " + fixed(zsafe_, 3) + " that clears every turn of the rotaries is above Z's limit " +
                               fixed(zl->second.max, 3) + "; using the limit");
      zsafe_ = zl->second.max;
    }
  }

  Program& program() { return prog_; }

  // Safe start: up to the transit height, turn the rotaries, over the first point, down its axis.
  void start(const ToolPose& pose, const Joints& j, double feed) {
    const Transit t = transit(pose, j);
    prog_.start = t.high;
    prog_.start.a = prog_.start.b = prog_.start.c = 0.0;
    rapid(prog_.start);
    rapid(t.high);
    rapid(t.retract);
    plunge(target(pose, j), feed);
  }

  // Back along the axis to the retract point and up to the transit height.
  void finish(const ToolPose& pose, const Joints& j) {
    const Transit t = transit(pose, j);
    rapid(t.retract);
    rapid(t.high);
  }

  // A link between rows too far apart to cut through: retract, rapid(s), approach and a feed plunge. With
  // the rotaries unchanged the rapid runs at the lowest height whose swept motion clears the obstacles;
  // where they turn, at the transit height (on a table machine the part turns with them, and that height
  // clears any turn).
  void link(const ToolPose& from_pose, const Joints& from, const ToolPose& to_pose, const Joints& to, double feed) {
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

  // A change of configuration between two solutions of (possibly different) poses: retract, turn at the
  // transit height, re-approach.
  void reposition(const ToolPose& from_pose, const Joints& from, const ToolPose& to_pose, const Joints& to, double feed) {
    const Transit a = transit(from_pose, from), b = transit(to_pose, to);
    rapid(a.retract);
    rapid(a.high);
    Joints turned = a.high;
    turned.a = b.high.a;
    turned.b = b.high.b;
    turned.c = b.high.c;
    check_turn(a.high, turned);
    rapid(turned);
    rapid(b.high);
    rapid(b.retract);
    plunge(target(to_pose, to), feed);
  }

  // A cutting block from (p0, j0) to (p1, j1) at `feed` mm/min along the tip path.
  void cut(const ToolPose& p0, const Joints& j0, const ToolPose& p1, const Joints& j1, double feed) {
    feed = std::min(feed, job_.machine.max_feed);
    const double d_tip = (p1.tip - p0.tip).norm();
    const double d_rot = std::max({std::abs(j1.a - j0.a), std::abs(j1.b - j0.b), std::abs(j1.c - j0.c)});
    const double d_xyz = Eigen::Vector3d(j1.x - j0.x, j1.y - j0.y, j1.z - j0.z).norm();
    if (d_tip < 1e-9 && d_rot < 1e-9 && d_xyz < 1e-9) return;  // a repeated row
    Block b = block(Motion::Linear, target(p1, j1));
    if (tcp_ || d_rot < 1e-9) {
      b.feed_mode = FeedMode::PerMinute;
      b.feed = feed;
    } else {
      // Inverse time: the tip at the feed, unless an axis would exceed its top speed. The controller times
      // the axes' moves as written, each end rounded to 4 decimals (gcode_writer): a block of 0.0002 mm
      // could read 50 % longer, and its F had driven X 58 % over max_feed (found by black-box testing).
      constexpr double kWritten = 1e-4;
      const double minutes = std::max({d_tip / feed, (d_xyz + std::sqrt(3.0) * kWritten) / job_.machine.max_feed,
                                       (d_rot + kWritten) / job_.machine.max_rotary_feed});
      b.feed_mode = FeedMode::InverseTime;
      b.feed = 1.0 / minutes;
    }
    prog_.blocks.push_back(b);
  }

  Joints target(const ToolPose& pose, const Joints& j) const {
    if (!tcp_) return j;
    Joints t = j;
    t.x = pose.tip.x();
    t.y = pose.tip.y();
    t.z = pose.tip.z();
    return t;
  }

 private:
  struct Transit {
    Joints retract;  // the tool backed off along its axis until it clears the part
    Joints high;     // further along the axis (or straight up) to the transit height
    bool high_within_limits = true;
  };

  // The tool pose at programmed joints (tcp: the tip itself, with `axis`).
  ToolPose pose_at(const Joints& j, const Eigen::Vector3d& axis) const {
    if (tcp_) return ToolPose{Eigen::Vector3d(j.x, j.y, j.z), axis};
    return kin_.forward(j);
  }

  // The machine's joints for programmed ones: under TCP the program holds the tip, and the machine's
  // linear axes are those that put it there at the rotaries (the limits are theirs).
  Joints machine_joints(const Joints& programmed) const {
    if (!tcp_) return programmed;
    return joints_for_tip([this](const Joints& j) { return kin_.forward(j); }, programmed,
                          Eigen::Vector3d(programmed.x, programmed.y, programmed.z));
  }
  bool machine_within(const Joints& programmed) const { return kin_.within_limits(machine_joints(programmed)); }

  // A turn of the rotaries at a fixed programmed point. Joint moves are straight in the joints, so their
  // ends decide; under TCP the linear axes follow the part round and can leave their limits between inside
  // ends, so the turn is checked every degree (the transit tests had skipped the limits under TCP).
  void check_turn(const Joints& from, const Joints& to) const {
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

  // Whether the rapids through `corners` (rotaries fixed, so each is a translation of the tool in the
  // part frame) stay within the limits and keep half of safe_z from the obstacles. Half: the corners
  // themselves clear by safe_z, so a move that starts at one has room before the margin is reached.
  bool rapids_clear(const std::vector<Joints>& corners, const Eigen::Vector3d& axis) const {
    const double margin = 0.5 * job_.machine.safe_z;
    for (size_t k = 0; k < corners.size(); ++k) {
      if (!machine_within(corners[k])) return false;
      if (k == 0) continue;
      const ToolPose p0 = pose_at(corners[k - 1], axis), p1 = pose_at(corners[k], axis);
      if (!check_.translation_clear(p0, p1.tip - p0.tip, margin)) return false;
    }
    return true;
  }

  // The lowest programmed Z from the higher of the two retracts up to the transit height at which the
  // rapids retract -> up -> across -> down -> retract clear (rapids_clear): 16 steps up to the transit
  // height, then 8 bisections between the last step that fails and the first that clears (so within
  // 1/4096 of that range of the lowest, where clearing is monotone in the height there). nullopt: none.
  std::optional<double> link_height(const Joints& a, const Joints& b, const Eigen::Vector3d& axis) const {
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

  // How far to back off along the axis: to the part's extent plus safe_z.
  double full_lift(const ToolPose& pose) const {
    return std::max(0.0, max_projection(bounds_, pose.axis) - pose.tip.dot(pose.axis)) + job_.machine.safe_z;
  }

  // The height (joint Z, or part Z for tcp) above which the rotaries may turn without hitting the part.
  double transit_height() const {
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

  // The retract and the point at the transit height above it. With obstacles the retract backs off only
  // as far as the body needs to clear them by safe_z (at least 1 mm, so that the plunge is a move), never
  // farther than full_lift; when the rise to the transit height (`check_rise`) would come within half of
  // safe_z of them, the retract is the full one, as without obstacles.
  Transit transit(const ToolPose& pose, const Joints& j, bool check_rise = true) {
    const double full = full_lift(pose);
    if (!check_.active()) return reachable(transit_at(pose, j, full, full));
    const double lift = check_.lowest_lift(pose, std::min(1.0, full), full, job_.machine.safe_z).value_or(full);
    Transit t = transit_at(pose, j, lift, full);
    if (!check_rise) return t;  // only the retract is used
    if (lift >= full) return reachable(t);
    const ToolPose low = pose_at(t.retract, pose.axis), high = pose_at(t.high, pose.axis);
    if (t.high_within_limits && check_.translation_clear(low, high.tip - low.tip, 0.5 * job_.machine.safe_z)) return t;
    return reachable(transit_at(pose, j, full, full));
  }

  Transit reachable(Transit t) const {
    if (!t.high_within_limits)
      throw JobError("the transit point X " + fixed(t.high.x, 3) + " Y " + fixed(t.high.y, 3) + " Z " + fixed(t.high.z, 3) +
                     " over a retract is outside the machine's limits (" + outside_limits(machine_joints(t.high)) + ")" +
                     (tcp_ ? "; under tool-centre-point control the transit height is the part's top + safe_z, which the "
                             "machine must reach at every retract's rotaries (the joint dialect caps it at Z's limit)"
                           : ""));
    return t;
  }

  // `full`: the lift that takes the tip safe_z beyond the part's extent along the axis (full_lift). From
  // there the whole part lies behind the plane through the tip normal to the axis, and a rise straight up
  // (axis.z >= 0) only moves away from that plane: the rise is vertical. From a shorter retract it goes on
  // along the axis (checked by `transit`), where a vertical rise could scrape a wall. Along an axis 84 deg
  // off vertical that had carried a head machine 2.3 m sideways to reach the transit height (found in
  // review).
  Transit transit_at(const ToolPose& pose, const Joints& j, double lift, double full) {
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
    }
    t.high.z = z;
    t.high_within_limits = machine_within(t.high);
    return t;
  }

  // The axes of j beyond the machine's limits, as "X 1343.8 > 500".
  std::string outside_limits(const Joints& j) const {
    std::string out;
    for (const AxisOutside& e : axes_outside_limits(job_.machine, j))
      out += (out.empty() ? "" : ", ") + std::string(1, e.axis) + " " + fixed(e.value, 3) +
             (e.value > e.limit.max ? " > " + fixed(e.limit.max, 3) : " < " + fixed(e.limit.min, 3));
    return out;
  }

  Block block(Motion motion, const Joints& target) const {
    Block b;
    b.motion = motion;
    b.target = target;
    b.tcp = tcp_;
    b.spindle_rpm = opt_.spindle_rpm;
    b.tool = opt_.tool_number;
    return b;
  }

  void rapid(const Joints& target) { prog_.blocks.push_back(block(Motion::Rapid, target)); }

  void plunge(const Joints& to, double feed) {
    Block b = block(Motion::Linear, to);
    b.feed_mode = FeedMode::PerMinute;
    b.feed = std::min(feed, job_.machine.max_feed) * opt_.plunge_feed_fraction;
    prog_.blocks.push_back(b);
  }

  const Kinematics& kin_;
  const PostJob& job_;
  const PostOptions& opt_;
  bool tcp_;
  Eigen::AlignedBox3d bounds_;
  const TransitChecker& check_;
  double zsafe_ = 0.0;
  int tries_warned_ = 0;
  Program prog_;
};

std::string segment_failure(size_t row, const LinearizeOptions& lo) {
  return "cannot linearise the move from row " + std::to_string(row) + " to row " + std::to_string(row + 1) +
         " within the tolerances (tip " + fixed(lo.tip_tolerance_mm, 4) + " mm, axis " + fixed(lo.axis_tolerance_deg, 4) +
         " deg)";
}

// The rows as tool poses with their feeds, and the box the transit moves must clear (part, tips, rows).
struct PostRows {
  std::vector<ToolPose> poses;
  std::vector<double> feeds;
  Eigen::AlignedBox3d bounds;
};

PostRows post_rows(const OrientedPath& path, const PostJob& job) {
  PostRows rows;
  rows.poses.resize(path.rows.size());
  rows.feeds.resize(path.rows.size());
  rows.bounds = job.part_bounds;
  for (size_t i = 0; i < path.rows.size(); ++i) {
    const OrientedRow& r = path.rows[i];
    rows.poses[i] = ToolPose{row_tip(r, job.tool), r.axis.normalized()};
    rows.feeds[i] = std::isnan(r.feed) ? job.feed : r.feed;
    // The program writes F with at most 8 decimals (gcode_writer's feed_word): a smaller feed would read as
    // F0, which a controller refuses. Named here, where the row is known, rather than at the writing.
    if (std::min(rows.feeds[i], job.machine.max_feed) < 1e-8) {
      char text[32];
      std::snprintf(text, sizeof text, "%g", rows.feeds[i]);
      throw PostRowError(i, std::string("feed ") + text + " mm/min is too small to write (it reads as F0)");
    }
    rows.bounds.extend(rows.poses[i].tip);
    rows.bounds.extend(r.p);
  }
  return rows;
}

// APT carries the tool tips and axes themselves; the program lists them as tcp targets.
Program apt_program(const PostRows& rows) {
  Program prog;
  for (size_t i = 0; i < rows.poses.size(); ++i) {
    Block b;
    b.target.x = rows.poses[i].tip.x();
    b.target.y = rows.poses[i].tip.y();
    b.target.z = rows.poses[i].tip.z();
    b.tcp = true;
    b.feed = rows.feeds[i];
    prog.blocks.push_back(b);
  }
  return prog;
}

LinearizeOptions linearize_options(const PostOptions& options, bool tcp) {
  LinearizeOptions lo;
  lo.tip_tolerance_mm = tcp ? std::numeric_limits<double>::infinity() : options.tip_tolerance_mm;
  lo.axis_tolerance_deg = options.axis_tolerance_deg;
  lo.pole_tolerance_deg = options.pole_tolerance_deg;
  return lo;
}

std::vector<Joints> by_rotary_distance(std::vector<Joints> v, const Joints& to) {
  std::sort(v.begin(), v.end(), [&](const Joints& x, const Joints& y) {
    return rotary_distance(x, to) < rotary_distance(y, to);
  });
  return v;
}

// Where the move from row i - 1 to row i is discontinuous (the limits force a change of configuration),
// one of the two ways below goes through a retract. Each leaves in `pieces` the blocks still to cut from
// (p0, j0) on and returns false when it finds no way.
struct RowMove {
  const Kinematics& kin;
  const PostRows& rows;
  const std::vector<Joints>& joints;
  const LinearizeOptions& lo;
  Builder& b;
  size_t i;
  ToolPose p0;
  Joints j0;
  std::vector<PosedJoints>& pieces;

  void cut_pieces() {
    for (const PosedJoints& q : pieces) {
      b.cut(p0, j0, q.pose, q.joints, rows.feeds[i]);
      p0 = q.pose;
      j0 = q.joints;
    }
  }

  // Take the previous row again in a configuration that runs on to this one.
  bool change_before() {
    for (const Joints& other : by_rotary_distance(all_solutions(p0, kin, joints[i]), joints[i])) {
      if (rotary_distance(other, j0) < 1e-6 || !linearize(kin, p0, other, rows.poses[i], joints[i], lo, pieces))
        continue;
      b.program().warnings.push_back("row " + std::to_string(i) +
                                     ": change of configuration before it (retract, turn, re-approach)");
      b.reposition(p0, j0, p0, other, rows.feeds[i]);
      j0 = other;
      return true;
    }
    return false;
  }

  // Finish the move in the present configuration and change it at this row.
  bool change_at() {
    for (const Joints& same : by_rotary_distance(all_solutions(rows.poses[i], kin, j0), j0)) {
      if (!linearize(kin, p0, j0, rows.poses[i], same, lo, pieces)) continue;
      cut_pieces();
      pieces.clear();
      b.program().warnings.push_back("row " + std::to_string(i) +
                                     ": change of configuration at it (retract, turn, re-approach)");
      b.reposition(rows.poses[i], j0, rows.poses[i], joints[i], rows.feeds[i]);
      p0 = rows.poses[i];
      j0 = joints[i];
      return true;
    }
    return false;
  }

  // The limits end the present configuration between the rows (a limited C reaching its end while the
  // axis turns on): cut in it up to where it ends, change there (retract, turn, re-approach) and cut on
  // to this row in the configuration chosen for it.
  bool change_between() {
    const ToolPose& p1 = rows.poses[i];
    auto pose_at = [&](double s) { return ToolPose{p0.tip + s * (p1.tip - p0.tip), slerp_axis(p0.axis, p1.axis, s)}; };
    // The present configuration at s: the solution nearest the previous row's joints, unless that is the
    // other configuration (half a turn of C away, or the tilt's sign changed far from the pole).
    constexpr double kSameConfiguration = 90.0;  // deg of rotary motion
    auto present = [&](double s, Joints& out) {
      const std::vector<Joints> near = by_rotary_distance(all_solutions(pose_at(s), kin, j0), j0);
      if (near.empty() || rotary_distance(near.front(), j0) > kSameConfiguration) return false;
      out = near.front();
      return true;
    };
    Joints jm = j0, probe;
    if (present(1.0, probe)) return false;  // not a limit between the rows: the other ways failed for another reason
    double s0 = 0.0, s1 = 1.0;
    for (int k = 0; k < 40; ++k) {
      const double s = 0.5 * (s0 + s1);
      if (present(s, probe)) s0 = s, jm = probe;
      else s1 = s;
    }
    if (s0 <= 0.0) return false;
    const ToolPose m = pose_at(s0);
    std::vector<PosedJoints> tail;
    for (const Joints& other : by_rotary_distance(all_solutions(m, kin, joints[i]), joints[i])) {
      tail.clear();
      if (rotary_distance(other, jm) < 1e-6 || !linearize(kin, m, other, p1, joints[i], lo, tail)) continue;
      pieces.clear();
      if (!linearize(kin, p0, j0, m, jm, lo, pieces)) return false;
      cut_pieces();
      b.program().warnings.push_back("row " + std::to_string(i) +
                                     ": change of configuration before it, where the limits end the move (retract, turn, re-approach)");
      b.reposition(m, jm, m, other, rows.feeds[i]);
      p0 = m;
      j0 = other;
      pieces = std::move(tail);
      return true;
    }
    return false;
  }
};

// The cutting blocks between consecutive rows, each move linearised within the tolerances.
void post_moves(Builder& b, const Kinematics& kin, const PostRows& rows, const std::vector<Joints>& joints,
                const LinearizeOptions& lo, double link_gap, const Progress& progress) {
  const std::vector<ToolPose>& poses = rows.poses;
  std::vector<PosedJoints> pieces;
  for (size_t i = 1; i < poses.size(); ++i) {
    if ((poses[i].tip - poses[i - 1].tip).norm() > link_gap) {
      // A jump (another pass, across a boss): linked, not cut through whatever lies between.
      b.link(poses[i - 1], joints[i - 1], poses[i], joints[i], rows.feeds[i]);
      continue;
    }
    pieces.clear();
    RowMove move{kin, rows, joints, lo, b, i, poses[i - 1], joints[i - 1], pieces};
    if (!linearize(kin, move.p0, move.j0, poses[i], joints[i], lo, pieces) && !move.change_before() &&
        !move.change_at() && !move.change_between())
      throw JobError(segment_failure(i - 1, lo));
    move.cut_pieces();
    if (i % 4096 == 0) report(progress, "post", 0.2 + 0.8 * double(i) / double(poses.size()));
  }
}

}  // namespace

Program post_program(const OrientedPath& path, const PostJob& job, const PostOptions& options,
                     const Progress& progress) {
  if (path.rows.empty()) throw JobError("the oriented path has no rows");
  const Dialect dialect = effective_dialect(options, job.machine);
  const Kinematics kin(job.machine, job.tool.length);
  const PostRows rows = post_rows(path, job);
  if (dialect == Dialect::Apt) return apt_program(rows);
  report(progress, "post", 0.0);
  const std::vector<Joints> joints = choose_joints(rows.poses, kin, options);
  report(progress, "post", 0.2);

  const bool tcp = dialect == Dialect::Tcp;
  const LinearizeOptions lo = linearize_options(options, tcp);
  const double link_gap = effective_link_gap(options, job.tool);
  if (!(link_gap > 0.0)) throw JobError("the link gap must be positive");
  const TransitChecker check(job);
  Builder b(kin, job, options, tcp, rows.bounds, check);
  b.start(rows.poses[0], joints[0], rows.feeds[0]);
  post_moves(b, kin, rows, joints, lo, link_gap, progress);
  b.finish(rows.poses.back(), joints.back());
  report(progress, "post", 1.0);
  return std::move(b.program());
}

}  // namespace tf
