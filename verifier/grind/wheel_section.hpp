// tiltfield (internal): the grinding wheel's section by a blank section plane, and 2-D convex hulls.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "tiltfield/grind/grind.hpp"
#include "tiltfield/grind/sections.hpp"

namespace tf::grind::detail {

// Precomputed per wheel pose: what the section loop needs without re-deriving it per section.
struct PoseInfo {
  WheelPose pose;
  Eigen::Vector3d u1, u2;  // unit vectors completing the spindle axis to a right-handed frame
  double z_lo = 0, z_hi = 0;  // z-range of the wheel, mm
  bool far = false;           // the wheel cannot reach the blank's cylinder at this pose
  // The blank's turn and the workhead's swivel (deg): between two poses that differ in either, the wheel's
  // section turns in the section plane (turning_sweep), where between others it only moves.
  double a = 0, w = 0;
};
// a_deg: the blank's turn A at the pose (numbers the generators where the spindle lies along the blank).
PoseInfo pose_info(const WheelPose& pose, const Wheel& wheel, const Blank& blank, double a_deg = 0.0);

// Appends points on the boundary of the wheel's section by the plane z = z0 (blank frame): the endpoints of
// each ring's chord (the "segments" of the section method), and, when the plane crosses the spindle axis steeply
// (|axis.z| > 0.5), where the wheel's generator lines pierce the plane. Their convex hull is the section.
// `trig` holds (cos, sin) of the generator angles (generator_table); empty: rings only. `ids` (when given)
// gets each point's identity (which ring and end, or which generator and profile segment), the same at
// every pose, so that a point can be followed from one pose to the next.
void wheel_section_points(const PoseInfo& info, const std::vector<Eigen::Vector2d>& profile, double z0,
                          const std::vector<Eigen::Vector2d>& trig, std::vector<Eigen::Vector2d>& out,
                          std::vector<int>* ids = nullptr);

// The profile with rings added along its segments, so that no segment between two rings runs farther than
// `short_side` mm both along the spindle and in radius, nor farther than 0.25 mm along the spindle. A plane that reaches a segment only
// past its smaller ring touches it at wheel_section_points' extreme point, and the section between that
// point and the next ring is taken as straight: wrong by up to a quarter of the segment's shorter side
// (a V-wheel's 10 mm flank given by its two ends was off by 0.5 mm).
std::vector<Eigen::Vector2d> rings_along_profile(const std::vector<Eigen::Vector2d>& profile, double short_side);

// The generator lines to sample on a wheel of radius `radius` (mm): at least options.generators, and enough
// that the chord between two neighbours' piercing points stays within options.chord_tolerance. A plane
// crossing the spindle at 60 deg or more (where generators are used) stretches the ring's section by up to
// 2, so the chord's sagitta is bounded by 2 R (1 - cos(pi / n)). 180 generators alone had left an R 300 wheel
// 0.045 mm shallow (black-box testing).
int generator_count(double radius, const SectionOptions& options);

// (cos, sin) of n equally spaced generator angles.
std::vector<Eigen::Vector2d> generator_table(int n);

// Lower bound of the distance (mm) from point p to the wheel at a pose: distance to its bounding cylinder.
double distance_bound(const PoseInfo& info, const Wheel& wheel, const Eigen::Vector3d& p);

// Convex hull (Andrew's monotone chain), counter-clockwise, no collinear points.
std::vector<Eigen::Vector2d> convex_hull(const std::vector<Eigen::Vector2d>& pts);

// The same as indices into `pts`.
std::vector<int> convex_hull_indices(const std::vector<Eigen::Vector2d>& pts);

// The area a wheel's section sweeps in its plane between two poses where it turns (the blank turned or the
// workhead swivelled), as counter-clockwise polygons whose union it is (turning_sweep.cpp): the sections'
// hulls, and for each hull edge whose ends are found at the other pose (by `ids`, wheel_section_points) the
// area it sweeps as its ends move straight there (any point the moving section covers is crossed by one of
// its edges). The hull of both sections instead joins opposite corners of the turned sections, a chord
// through material the wheel leaves: an error first order in the turn, where this one is second order (the
// ends' arcs taken as chords). An edge with an end that has no counterpart (a ring entering or leaving the
// plane) is left to the sections and the other edges. False when a section is degenerate or no edge of
// either can be followed; `out` is then not to be used.
bool turning_sweep(const std::vector<Eigen::Vector2d>& p0, const std::vector<int>& id0,
                   const std::vector<Eigen::Vector2d>& p1, const std::vector<int>& id1,
                   std::vector<std::vector<Eigen::Vector2d>>& out);

}  // namespace tf::grind::detail
