// tiltfield (internal to the post-processor): the program as it is built, block by block: the safe start
// and finish, cutting blocks with their feeds (inverse time where the rotaries move), links between rows
// and changes of configuration through the transit height, each retract checked against the obstacles.
#pragma once
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "post_internal.hpp"
#include "transit_check.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/post/post.hpp"

namespace tf::post_detail {

class Builder {
 public:
  Builder(const Kinematics& kin, const PostJob& job, const PostOptions& opt, bool tcp, Eigen::AlignedBox3d bounds,
          const TransitChecker& check)
      : kin_(kin), job_(job), opt_(opt), tcp_(tcp), bounds_(bounds), check_(check) {
    zsafe_ = transit_height();
    const auto zl = job.machine.limits.find('Z');
    if (!tcp_ && zl != job.machine.limits.end() && zsafe_ > zl->second.max) {
      prog_.warnings.push_back("the transit height Z " + fixed(zsafe_, 3) + " that clears every turn of the rotaries is above Z's limit " +
                               fixed(zl->second.max, 3) + "; using the limit" +
                               (check_.active() ? ", each turn there and the move after it checked"
                                                : " (no stock, fixtures or check surfaces to check the turns against)"));
      clearing_height_ = zsafe_;
      zsafe_ = zl->second.max;
    }
  }

  Program& program() { return prog_; }

  // Safe start: up to the transit height, over the first point, turn the rotaries, down its axis.
  void start(const ToolPose& pose, const Joints& j, double feed);

  // Back along the axis to the retract point and up to the transit height.
  void finish(const ToolPose& pose, const Joints& j) {
    const Transit t = transit(pose, j);
    rapid(t.retract);
    if (t.via) rapid(*t.via);
    rapid(t.high);
  }

  // A link between rows too far apart to cut through: retract, rapid(s), approach and a feed plunge. With
  // the rotaries unchanged the rapid runs at the lowest height whose swept motion clears the obstacles;
  // where they turn, at the transit height (on a table machine the part turns with them, and that height
  // clears any turn).
  void link(const ToolPose& from_pose, const Joints& from, const ToolPose& to_pose, const Joints& to, double feed);

  // A change of configuration between two solutions of (possibly different) poses: retract, turn at the
  // transit height, re-approach.
  void reposition(const ToolPose& from_pose, const Joints& from, const ToolPose& to_pose, const Joints& to, double feed);

  // A cutting block from (p0, j0) to (p1, j1) at `feed` mm/min along the tip path.
  void cut(const ToolPose& p0, const Joints& j0, const ToolPose& p1, const Joints& j1, double feed);

  // The programmed joints of a row's pose solved as j: under TCP the tip with j's rotaries; otherwise
  // the rotaries rounded as written and the X Y Z that put the tip at pose.tip at them.
  Joints target(const ToolPose& pose, const Joints& j) const;

 private:
  struct Transit {
    Joints retract;  // the tool backed off along its axis until it clears the part
    Joints high;     // further along the axis (or straight up) to the transit height
    // Between them, where the rise goes on along the axis only to the full retract and then straight up:
    // that point (the plunge from the shorter retract stays short).
    std::optional<Joints> via;
    bool high_within_limits = true;
    // How far sideways (programmed X Y) the rise along the axis takes the tool beyond where the full
    // retract would, mm (0: straight up, or no farther).
    double sideways_beyond_full = 0.0;
  };

  // The tool pose at programmed joints (tcp: the tip itself, with `axis`).
  ToolPose pose_at(const Joints& j, const Eigen::Vector3d& axis) const {
    if (tcp_) return ToolPose{Eigen::Vector3d(j.x, j.y, j.z), axis};
    return kin_.forward(j);
  }

  // Every axis of j as the program writes it (kAxisDecimals in the work offset's frame).
  Joints written(const Joints& j) const;

  // The machine's linear axes' peak speed over a TCP block between programmed joints (the tip and the
  // rotaries), as a length per block (mm): divided by the block's time, it is their top speed.
  double tcp_linear_path(const Joints& from, const Joints& to) const;

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
  void check_turn(const Joints& from, const Joints& to) const;

  // Under a transit height lowered to Z's limit (joint dialect), which no longer clears every turn: the
  // turn from `from` to `turned` there and the move on to `over` (rotaries fixed: a translation) must keep
  // half of safe_z from the obstacles, or the job fails naming the turn. Without obstacles nothing is
  // checked (the warning stays).
  void check_lowered_turn(const Joints& from, const Joints& turned, const Joints& over) const;

  // Whether the rapids through `corners` (rotaries fixed, so each is a translation of the tool in the
  // part frame) stay within the limits and keep half of safe_z from the obstacles. Half: the corners
  // themselves clear by safe_z, so a move that starts at one has room before the margin is reached.
  bool rapids_clear(const std::vector<Joints>& corners, const Eigen::Vector3d& axis) const;

  // The lowest programmed Z from the higher of the two retracts up to the transit height at which the
  // rapids retract -> up -> across -> down -> retract clear (rapids_clear): 16 steps up to the transit
  // height, then 8 bisections between the last step that fails and the first that clears (so within
  // 1/4096 of that range of the lowest, where clearing is monotone in the height there). nullopt: none.
  std::optional<double> link_height(const Joints& a, const Joints& b, const Eigen::Vector3d& axis) const;

  // How far to back off along the axis: to the part's extent plus safe_z.
  double full_lift(const ToolPose& pose) const {
    return std::max(0.0, max_projection(bounds_, pose.axis) - pose.tip.dot(pose.axis)) + job_.machine.safe_z;
  }

  // The height (joint Z, or part Z for tcp) above which the rotaries may turn without hitting the part.
  double transit_height() const;

  // The retract and the point at the transit height above it. With obstacles the retract backs off only
  // as far as the body needs to clear them by safe_z (at least 1 mm, so that the plunge is a move), never
  // farther than full_lift; when the rise to the transit height (`check_rise`) would come within half of
  // safe_z of them, the retract is the full one, as without obstacles.
  Transit transit(const ToolPose& pose, const Joints& j, bool check_rise = true);

  Transit reachable(Transit t) const;

  // `full`: the lift that takes the tip safe_z beyond the part's extent along the axis (full_lift). From
  // there the whole part lies behind the plane through the tip normal to the axis, and a rise straight up
  // (axis.z >= 0) only moves away from that plane: the rise is vertical. From a shorter retract it goes on
  // along the axis (checked by `transit`), where a vertical rise could scrape a wall. Along an axis 84 deg
  // off vertical that had carried a head machine 2.3 m sideways to reach the transit height (found in
  // review).
  Transit transit_at(const ToolPose& pose, const Joints& j, double lift, double full);

  // The axes of j beyond the machine's limits, as "X 1343.8 > 500".
  std::string outside_limits(const Joints& j) const;

  Block block(Motion motion, const Joints& target) const;

  void rapid(const Joints& target) { prog_.blocks.push_back(block(Motion::Rapid, target)); }

  void plunge(const Joints& to, double feed);

  const Kinematics& kin_;
  const PostJob& job_;
  const PostOptions& opt_;
  bool tcp_;
  Eigen::AlignedBox3d bounds_;
  const TransitChecker& check_;
  double zsafe_ = 0.0;
  std::optional<double> clearing_height_;  // the transit height that clears every turn, where zsafe_ is lower
  int tries_warned_ = 0;
  Program prog_;
};

}  // namespace tf::post_detail
