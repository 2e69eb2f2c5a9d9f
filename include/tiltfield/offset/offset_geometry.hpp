// tiltfield offset: exact 2-D line and circular-arc primitives (double precision, no polygonisation).
//
// One value type, Segment, stands for a line or an arc; free functions evaluate, measure, split and
// intersect segments. Lengths in mm, angles in radians.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace tf::offset {

// The z component of u x v (u, v in the plane): > 0 when v turns left of u.
inline double cross(const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); }

// Where a trajectory segment comes from; decides which exactness rule applies to it.
enum class SegmentKind {
  Element,    // a profile element, or its exact offset (distance to the profile == gap)
  RoundJoin,  // arc of radius gap about a profile vertex (distance == gap)
  SharpJoin,  // extension of a neighbour up to the intersection of the offsets (distance >= gap)
  Fitted,     // arc approximating a variable-gap offset within OffsetOptions::arc_tolerance
  // Variable gap only: the stretch next to a junction where another profile element is closest. The gap
  // law jumps across the medial axis (the two closest points have different s), so no continuous path
  // can keep distance == gap(s*) there; these stretches keep the intersection join and their distance
  // is >= the law's value at the closest point (never closer).
  Transition,
};

// A line (sweep == 0) or a circular arc from a to b. For arcs: centre c, radius r > 0 and the signed
// swept angle (positive counter-clockwise), |sweep| in (0, 2*pi). a and b are stored exactly so that
// chained segments share bit-identical end points.
struct Segment {
  Eigen::Vector2d a{0, 0}, b{0, 0};  // start and end, mm
  Eigen::Vector2d c{0, 0};           // arc centre, mm (unused for lines)
  double r = 0;                      // arc radius, mm (0 for lines)
  double sweep = 0;                  // signed arc angle, rad (0 for lines)
  double g0 = 0, g1 = 0;             // trajectory only: the gap at the start and the end, mm
  int line = 0;                      // 1-based line of the profile element it comes from, 0 for none
  SegmentKind kind = SegmentKind::Element;
  bool is_arc() const { return sweep != 0; }
};

// A line from a to b.
Segment make_line(const Eigen::Vector2d& a, const Eigen::Vector2d& b);
// An arc about c from angle theta0 (rad) through the signed angle sweep (rad), radius r (mm).
Segment make_arc(const Eigen::Vector2d& c, double r, double theta0, double sweep);
// An arc about c from a to b turning counter-clockwise (ccw) or clockwise; the sweep is taken in
// (0, 2*pi) in that direction. The radius is |a - c|; b is kept exactly as given.
Segment make_arc_to(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c, bool ccw);

double length(const Segment& s);
double start_angle(const Segment& s);  // arcs: angle of a - c (rad)
// Point at parameter t in [0, 1] (arc-length proportional); t = 0 and t = 1 return a and b exactly.
Eigen::Vector2d point_at(const Segment& s, double t);
// Unit tangent in the direction of travel at parameter t.
Eigen::Vector2d tangent_at(const Segment& s, double t);
// Left unit normal (tangent turned by +90 degrees) at parameter t.
Eigen::Vector2d left_normal_at(const Segment& s, double t);
Eigen::AlignedBox2d bounding_box(const Segment& s);
// The part of s between parameters t0 < t1.
Segment sub_segment(const Segment& s, double t0, double t1);
Segment reversed(const Segment& s);

// Closest point of s to q: returns the distance (mm) and writes the parameter of the closest point.
double distance(const Segment& s, const Eigen::Vector2d& q, double* t_closest = nullptr);

// Parameter of a point known to lie on s (or on its supporting line or circle). For arcs the result is
// the angle from a in the direction of travel over |sweep|, in [0, 2*pi/|sweep|).
double parameter_of(const Segment& s, const Eigen::Vector2d& p);

struct Crossing {
  Eigen::Vector2d p;  // the common point, mm
  double t1, t2;      // its parameters on the first and the second segment, clamped to [0, 1]
};
// Common points of two segments. tol (mm): points within tol of both segments count, tangencies within
// tol give one point, overlapping collinear lines or co-circular arcs give the ends of the overlap.
std::vector<Crossing> intersect(const Segment& s1, const Segment& s2, double tol);

// Signed area (mm^2) enclosed by a closed chain of segments, positive when counter-clockwise.
double signed_area(const std::vector<Segment>& chain);
double chain_length(const std::vector<Segment>& chain);

}  // namespace tf::offset
