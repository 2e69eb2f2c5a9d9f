// tiltfield (internal): the grinding wheel's section by a blank section plane, and 2-D convex hulls.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "tiltfield/grind/grind.hpp"

namespace tf::grind::detail {

// Precomputed per wheel pose: what the section loop needs without re-deriving it per section.
struct PoseInfo {
  WheelPose pose;
  Eigen::Vector3d u1, u2;  // unit vectors completing the spindle axis to a right-handed frame
  double z_lo = 0, z_hi = 0;  // z-range of the wheel, mm
  bool far = false;           // the wheel cannot reach the blank's cylinder at this pose
};
PoseInfo pose_info(const WheelPose& pose, const Wheel& wheel, const Blank& blank);

// Appends points on the boundary of the wheel's section by the plane z = z0 (blank frame): the endpoints of
// each ring's chord (the "segments" of the section method), and, when the plane crosses the spindle axis steeply
// (|axis.z| > 0.5), where the wheel's generator lines pierce the plane. Their convex hull is the section.
// `trig` holds (cos, sin) of the generator angles (generator_table); empty: rings only.
void wheel_section_points(const PoseInfo& info, const std::vector<Eigen::Vector2d>& profile, double z0,
                          const std::vector<Eigen::Vector2d>& trig, std::vector<Eigen::Vector2d>& out);

// (cos, sin) of n equally spaced generator angles.
std::vector<Eigen::Vector2d> generator_table(int n);

// Lower bound of the distance (mm) from point p to the wheel at a pose: distance to its bounding cylinder.
double distance_bound(const PoseInfo& info, const Wheel& wheel, const Eigen::Vector3d& p);

// Convex hull (Andrew's monotone chain), counter-clockwise, no collinear points. `pts` is reordered.
std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d>& pts);

}  // namespace tf::grind::detail
