// tiltfield (internal to the post-processor): clearance of the tool body to the stock, the fixtures and
// the check surfaces, for the moves the post adds between cuts (approach, retract, links).
//
// In: a PostJob's tool and obstacles (part frame, mm) and tool poses (tip, unit axis). Out: signed
// clearances in mm (distance minus the body's radius, negative when the body touches or is inside the
// stock), the least retract lift along the axis that clears by a margin, and whether a straight
// translation of the body keeps a margin throughout. The body is a stack of capsules enclosing the real
// one (see body_capsules), so every answer errs on the safe side.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <optional>
#include <vector>

#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/triangle_bvh.hpp"
#include "tiltfield/post/post.hpp"

namespace tf::post_detail {

// The points within `radius` of the tool-axis segment from h0 to h1 mm above the tip.
struct BodyCapsule {
  double h0 = 0.0, h1 = 0.0, radius = 0.0;
};

// Capsules that enclose the whole tool: the end form and flutes ([cl_height, flute_length], the cutter
// radius: this holds the ball, a flat end's disk and a bull's torus), the shank, and every holder segment.
// Conservative: each capsule adds a half-sphere at both ends, and the radii are raised to be
// non-decreasing toward the spindle, so that a retract along the tool's own axis sweeps only the body at
// its start plus the top capsule's extension (see TransitChecker::lowest_lift).
std::vector<BodyCapsule> body_capsules(const Tool& tool);

class TransitChecker {
 public:
  // Builds one hierarchy for the stock (a solid) and one for the fixtures and check surfaces together
  // (distance only); the job's meshes are not referenced afterwards.
  explicit TransitChecker(const PostJob& job);

  bool active() const { return !stock_.empty() || !surfaces_.empty(); }

  // Signed clearance of the capsule around segment [a, b] with `radius`: the least distance to the
  // obstacles minus the radius; -(depth + radius) when the segment lies inside the stock, -radius when it
  // meets its surface. Values at or above `enough` come back as `enough` (the search stops there).
  // Moving the capsule by d changes the true value by at most d, and the value returned never exceeds it.
  double capsule_clearance(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius, double enough) const;

  // The least signed clearance over the body's capsules at `pose`, capped at `enough` as above.
  double clearance(const ToolPose& pose, double enough) const;

  // The least lift along pose.axis in [min_lift, max_lift] at which the body clears by `margin`, and
  // whose motion out of `pose` touches nothing: the body's radii grow toward the spindle, so backing off
  // along its own axis sweeps the body at `pose` (where the tool already is) plus the top capsule
  // lengthened by the lift, which is checked. Conservative advancement: from a lift whose clearance is c
  // the next lift that can clear is at least margin - c higher. nullopt: none within max_lift.
  std::optional<double> lowest_lift(const ToolPose& pose, double min_lift, double max_lift, double margin) const;

  // Whether the body translated from `pose` by `move` (its axis fixed) keeps `margin` throughout.
  // Conservative advancement: from a position with clearance c the body may move c - margin before it can
  // come within the margin, so the positions checked are at most that far apart; a position closer than
  // margin + kMinStepMm fails (so the steps never shrink below it).
  bool translation_clear(const ToolPose& pose, const Eigen::Vector3d& move, double margin) const;

  // Whether the body keeps `margin` through a turn of the rotaries, given as its poses at s in [0, 1]
  // (`pose_at`) and the largest angle in rad that any rotary turns. Checked at poses whose body points
  // are at most a step D apart, D bounded by the axis segment's ends' chords plus the angle times the
  // widest capsule's radius; each pose must clear by margin + D, which also covers the arcs' bulge
  // beyond their chords between two poses. At most 4 096 poses: a turn that needs more fails.
  bool turn_clear(const std::function<ToolPose(double)>& pose_at, double turn_rad, double margin) const;

  static constexpr double kMinStepMm = 0.01;

 private:
  bool inside_stock(const Eigen::Vector3d& p) const;
  double segment_distance(const TriangleBvh& bvh, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          double start) const;

  std::vector<BodyCapsule> capsules_;
  TriangleBvh stock_;
  TriangleBvh surfaces_;
};

}  // namespace tf::post_detail
