// The post-processor's main loop: rows -> tool poses -> joints -> linearised blocks, with the safe
// approach, retract, links between rows too far apart to cut through and (where the limits force one)
// change of configuration.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "post_internal.hpp"
#include "program_builder.hpp"
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


std::string segment_failure(size_t row, const LinearizeOptions& lo) {
  // The tcp dialect bounds no tip deviation (the controller keeps the tip): its infinite tolerance had
  // crashed the message's number formatting (black-box testing).
  const std::string tip = std::isfinite(lo.tip_tolerance_mm) ? "tip " + fixed(lo.tip_tolerance_mm, 4) + " mm, " : "";
  return "cannot linearise the move from row " + std::to_string(row) + " to row " + std::to_string(row + 1) +
         " within the tolerances (" + tip + "axis " + fixed(lo.axis_tolerance_deg, 4) + " deg)";
}

// Where a move between two reachable rows cannot be followed because its axis, turning along the great
// circle from one row's to the other's, passes a pose no joint setting reaches (beyond a tilt limit): the
// path's fault, named at its row as an unreachable row is. Empty when every sampled pose is reachable.
std::string unreachable_between(const Kinematics& kin, const ToolPose& p0, const ToolPose& p1, const Joints& j0,
                                const PostOptions& options) {
  InverseOptions io;
  io.pole_tolerance_deg = options.pole_tolerance_deg;
  constexpr int kSamples = 64;
  for (int k = 1; k < kSamples; ++k) {
    const double s = double(k) / kSamples;
    const ToolPose p{p0.tip + s * (p1.tip - p0.tip), slerp_axis(p0.axis, p1.axis, s)};
    if (kin.inverse(p, j0, io).empty())
      return "the axis turning to this row along its great circle leaves the machine's reach " +
             std::to_string(int(std::lround(100.0 * s))) + " % of the way from the row before: " +
             unreachable_reason(p, kin, options);
  }
  return {};
}

// The rows as tool poses with their feeds, and the box the transit moves must clear (part, tips, rows).
struct PostRows {
  std::vector<ToolPose> poses;
  std::vector<double> feeds;
  std::vector<Approach> approach;  // how each row is reached (OrientedRow::approach)
  Eigen::AlignedBox3d bounds;
};

PostRows post_rows(const OrientedPath& path, const PostJob& job) {
  PostRows rows;
  rows.poses.resize(path.rows.size());
  rows.feeds.resize(path.rows.size());
  rows.approach.resize(path.rows.size());
  rows.bounds = job.part_bounds;
  for (size_t i = 0; i < path.rows.size(); ++i) {
    const OrientedRow& r = path.rows[i];
    rows.poses[i] = ToolPose{row_tip(r, job.tool), r.axis.normalized()};
    rows.feeds[i] = std::isnan(r.feed) ? job.feed : r.feed;
    rows.approach[i] = r.approach;
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
  std::vector<Joints>& joints;
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

  // Reach this row in another of its solutions that the present configuration runs on to, and keep it
  // for the rows after: the choice made for the whole path is a least-motion estimate, and where it
  // cannot be followed without a retract (a fast azimuth just outside the pole cone, the tilt's sign
  // flipped) staying in the present configuration, C swinging, can.
  bool stay_in_configuration() {
    for (const Joints& same : by_rotary_distance(all_solutions(rows.poses[i], kin, j0), j0)) {
      if (rotary_distance(same, joints[i]) < 1e-6 || !linearize(kin, p0, j0, rows.poses[i], same, lo, pieces)) continue;
      joints[i] = same;
      return true;
    }
    return false;
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
    // The present configuration followed from parameter s_from (joints `from`) to s: the solution
    // nearest `from`, unless that is the other configuration: half a turn of C away, or the tilt's sign
    // changed where the wanted axis does not pass the pole's cone (near the pole the mirror solution is a
    // small rotary move away, but the joints cannot follow the axis into it). Followed in steps, as C may
    // turn by more than a quarter turn within one move near the pole.
    constexpr double kSameConfiguration = 90.0;  // deg of rotary motion
    const KinematicsType kt = kin.machine().kinematics;
    auto follow = [&](const Joints& from, double s_from, double s, Joints& out) {
      const ToolPose at = pose_at(s);
      const bool through_cone = arc_pole_distance(pose_at(s_from).axis, at.axis) < lo.pole_tolerance_deg;
      for (const Joints& j : by_rotary_distance(all_solutions(at, kin, from), from)) {
        if (rotary_distance(j, from) > kSameConfiguration) return false;
        if (!through_cone && tilt_of(j, kt) * tilt_of(from, kt) < 0.0) continue;
        out = j;
        return true;
      }
      return false;
    };
    constexpr int kSteps = 32;
    Joints jm = j0, probe;
    double s0 = 0.0, s1 = 1.0;
    for (int q = 1; q <= kSteps; ++q) {
      const double s = double(q) / kSteps;
      if (!follow(jm, s0, s, probe)) {
        s1 = s;
        break;
      }
      s0 = s, jm = probe;
    }
    if (s0 >= 1.0) return false;  // not a limit between the rows: the other ways failed for another reason
    const Joints last = jm;
    const double s_last = s0;
    for (int q = 0; q < 40; ++q) {
      const double s = 0.5 * (s0 + s1);
      if (follow(last, s_last, s, probe)) s0 = s, jm = probe;
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
void post_moves(Builder& b, const Kinematics& kin, const PostRows& rows, std::vector<Joints>& joints,
                const LinearizeOptions& lo, const PostOptions& options, double link_gap, const Progress& progress) {
  const std::vector<ToolPose>& poses = rows.poses;
  std::vector<PosedJoints> pieces;
  for (size_t i = 1; i < poses.size(); ++i) {
    if (linked_to(rows.approach[i], (poses[i].tip - poses[i - 1].tip).norm(), link_gap)) {
      // A jump (another pass, across a boss): linked, not cut through whatever lies between.
      b.link(poses[i - 1], joints[i - 1], poses[i], joints[i], rows.feeds[i]);
      continue;
    }
    pieces.clear();
    RowMove move{kin, rows, joints, lo, b, i, poses[i - 1], joints[i - 1], pieces};
    if (!linearize(kin, move.p0, move.j0, poses[i], joints[i], lo, pieces) && !move.stay_in_configuration() &&
        !move.change_before() && !move.change_at() && !move.change_between()) {
      const std::string beyond = unreachable_between(kin, poses[i - 1], poses[i], joints[i - 1], options);
      if (!beyond.empty()) throw PostRowError(i, beyond);
      throw JobError(segment_failure(i - 1, lo));
    }
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
  std::vector<Joints> joints = choose_joints(rows.poses, kin, options);  // a row may take another on the way
  report(progress, "post", 0.2);

  const bool tcp = dialect == Dialect::Tcp;
  const LinearizeOptions lo = linearize_options(options, tcp);
  const double link_gap = effective_link_gap(options, job.tool);
  if (!(link_gap > 0.0)) throw JobError("the link gap must be positive");
  const TransitChecker check(job);
  Builder b(kin, job, options, tcp, rows.bounds, check);
  b.start(rows.poses[0], joints[0], rows.feeds[0]);
  post_moves(b, kin, rows, joints, lo, options, link_gap, progress);
  b.finish(rows.poses.back(), joints.back());
  report(progress, "post", 1.0);
  return std::move(b.program());
}

}  // namespace tf
