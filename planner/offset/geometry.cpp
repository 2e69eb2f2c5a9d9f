// Exact line/arc primitives for the offset generator. See tiltfield/offset_geometry.hpp.
#include "tiltfield/offset/offset_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tf::offset {
namespace {
using Eigen::Vector2d;
constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

Vector2d perp(const Vector2d& v) { return {-v.y(), v.x()}; }
Vector2d unit_dir(double theta) { return {std::cos(theta), std::sin(theta)}; }

// Angle from direction u0 to u in the arc's direction of travel, in [0, 2*pi).
double travel_angle(const Segment& s, const Vector2d& u) {
  const Vector2d u0 = s.a - s.c;
  double d = std::atan2(cross(u0, u), u0.dot(u));
  if (s.sweep < 0) d = -d;
  if (d < 0) d += kTwoPi;
  return d;
}

// Parameter of p on arc s when it lies within the sweep up to an angular tolerance; -1 otherwise.
double on_arc(const Segment& s, const Vector2d& p, double tol) {
  const double d = travel_angle(s, p - s.c);
  const double sw = std::abs(s.sweep);
  const double eps = tol / s.r;
  if (d <= sw + eps) return std::min(d / sw, 1.0);
  if (d >= kTwoPi - eps) return 0.0;
  return -1.0;
}

// Parameter of p on line s when within the segment up to tol (mm); -1 otherwise.
double on_line(const Segment& s, const Vector2d& p, double tol) {
  const Vector2d d = s.b - s.a;
  const double L2 = d.squaredNorm();
  const double t = (p - s.a).dot(d) / L2;
  const double eps = tol / std::sqrt(L2);
  if (t < -eps || t > 1 + eps) return -1.0;
  return std::clamp(t, 0.0, 1.0);
}

double param_within(const Segment& s, const Vector2d& p, double tol) {
  return s.is_arc() ? on_arc(s, p, tol) : on_line(s, p, tol);
}

void push_if_on_both(const Segment& s1, const Segment& s2, const Vector2d& p, double tol, std::vector<Crossing>& out) {
  const double t1 = param_within(s1, p, tol);
  if (t1 < 0) return;
  const double t2 = param_within(s2, p, tol);
  if (t2 < 0) return;
  for (const auto& c : out)
    if ((c.p - p).norm() <= tol) return;
  out.push_back({p, t1, t2});
}

std::vector<Crossing> line_line(const Segment& s1, const Segment& s2, double tol) {
  std::vector<Crossing> out;
  const Vector2d d1 = s1.b - s1.a, d2 = s2.b - s2.a;
  const double den = cross(d1, d2);
  const double n1 = d1.norm(), n2 = d2.norm();
  if (std::abs(den) <= 1e-14 * n1 * n2) {
    // Parallel: only collinear overlaps meet; report the overlap's ends.
    if (std::abs(cross(d1, s2.a - s1.a)) / n1 > tol) return out;
    for (const Vector2d& p : {s1.a, s1.b, s2.a, s2.b}) push_if_on_both(s1, s2, p, tol, out);
    return out;
  }
  const Vector2d w = s2.a - s1.a;
  const double t = cross(w, d2) / den;
  const Vector2d p = s1.a + t * d1;
  push_if_on_both(s1, s2, p, tol, out);
  return out;
}

std::vector<Crossing> line_arc(const Segment& ln, const Segment& arc, double tol, bool swap) {
  std::vector<Crossing> out;
  const Vector2d d = ln.b - ln.a;
  const double A = d.squaredNorm();
  const double t0 = -(ln.a - arc.c).dot(d) / A;
  const Vector2d foot = ln.a + t0 * d;
  const double h = (foot - arc.c).norm();
  std::vector<Vector2d> pts;
  if (h > arc.r + tol) return out;
  if (h >= arc.r - tol * 1e-3 || arc.r * arc.r - h * h <= 0) {
    pts.push_back(foot);
  } else {
    const double dt = std::sqrt(arc.r * arc.r - h * h) / std::sqrt(A);
    pts.push_back(ln.a + (t0 - dt) * d);
    pts.push_back(ln.a + (t0 + dt) * d);
  }
  for (const auto& p : pts) {
    if (swap)
      push_if_on_both(arc, ln, p, tol, out);
    else
      push_if_on_both(ln, arc, p, tol, out);
  }
  return out;
}

std::vector<Crossing> arc_arc(const Segment& s1, const Segment& s2, double tol) {
  std::vector<Crossing> out;
  const Vector2d dc = s2.c - s1.c;
  const double d = dc.norm();
  if (d <= tol * 1e-3) {
    // Concentric: only co-circular arcs meet; report the overlap's ends.
    if (std::abs(s1.r - s2.r) > tol) return out;
    for (const Vector2d& p : {s1.a, s1.b, s2.a, s2.b}) push_if_on_both(s1, s2, p, tol, out);
    return out;
  }
  if (d > s1.r + s2.r + tol || d < std::abs(s1.r - s2.r) - tol) return out;
  const double x = (d * d + s1.r * s1.r - s2.r * s2.r) / (2 * d);
  const double h2 = s1.r * s1.r - x * x;
  const Vector2d e = dc / d;
  const Vector2d base = s1.c + x * e;
  if (h2 <= 0) {
    push_if_on_both(s1, s2, base, tol, out);
    return out;
  }
  const double h = std::sqrt(h2);
  push_if_on_both(s1, s2, base + h * perp(e), tol, out);
  push_if_on_both(s1, s2, base - h * perp(e), tol, out);
  return out;
}
}  // namespace

Segment make_line(const Vector2d& a, const Vector2d& b) {
  Segment s;
  s.a = a;
  s.b = b;
  return s;
}

Segment make_arc(const Vector2d& c, double r, double theta0, double sweep) {
  Segment s;
  s.c = c;
  s.r = r;
  s.sweep = sweep;
  s.a = c + r * unit_dir(theta0);
  s.b = c + r * unit_dir(theta0 + sweep);
  return s;
}

Segment make_arc_to(const Vector2d& a, const Vector2d& b, const Vector2d& c, bool ccw) {
  Segment s;
  s.a = a;
  s.b = b;
  s.c = c;
  s.r = (a - c).norm();
  s.sweep = ccw ? 1.0 : -1.0;  // direction only, for travel_angle
  double d = travel_angle(s, b - c);
  if (d <= 0) d = kTwoPi;
  s.sweep = ccw ? d : -d;
  return s;
}

double length(const Segment& s) { return s.is_arc() ? s.r * std::abs(s.sweep) : (s.b - s.a).norm(); }

double start_angle(const Segment& s) { return std::atan2(s.a.y() - s.c.y(), s.a.x() - s.c.x()); }

Vector2d point_at(const Segment& s, double t) {
  if (t <= 0) return s.a;
  if (t >= 1) return s.b;
  if (!s.is_arc()) return s.a + t * (s.b - s.a);
  return s.c + s.r * unit_dir(start_angle(s) + t * s.sweep);
}

Vector2d tangent_at(const Segment& s, double t) {
  if (!s.is_arc()) return (s.b - s.a).normalized();
  const Vector2d radial = unit_dir(start_angle(s) + std::clamp(t, 0.0, 1.0) * s.sweep);
  return s.sweep > 0 ? perp(radial) : Vector2d(-perp(radial));
}

Vector2d left_normal_at(const Segment& s, double t) { return perp(tangent_at(s, t)); }

Eigen::AlignedBox2d bounding_box(const Segment& s) {
  Eigen::AlignedBox2d box(s.a);
  box.extend(s.b);
  if (!s.is_arc()) return box;
  // Add the axis-extreme points the arc passes through.
  for (int k = 0; k < 4; ++k) {
    const Vector2d u = unit_dir(k * kPi / 2);
    if (travel_angle(s, u) <= std::abs(s.sweep)) box.extend(Vector2d(s.c + s.r * u));
  }
  return box;
}

Segment sub_segment(const Segment& s, double t0, double t1) {
  Segment out = s;
  out.a = point_at(s, t0);
  out.b = point_at(s, t1);
  if (s.is_arc()) out.sweep = s.sweep * (t1 - t0);
  out.g0 = s.g0 + (s.g1 - s.g0) * t0;
  out.g1 = s.g0 + (s.g1 - s.g0) * t1;
  return out;
}

Segment reversed(const Segment& s) {
  Segment out = s;
  std::swap(out.a, out.b);
  std::swap(out.g0, out.g1);
  out.sweep = -s.sweep;
  return out;
}

double distance(const Segment& s, const Vector2d& q, double* t_closest) {
  double t = 0;
  if (!s.is_arc()) {
    const Vector2d d = s.b - s.a;
    t = std::clamp((q - s.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  } else {
    const Vector2d v = q - s.c;
    const double rho = v.norm();
    const double ang = rho > 0 ? travel_angle(s, v) : 0.0;
    const double sw = std::abs(s.sweep);
    if (rho > 0 && ang <= sw) {
      if (t_closest) *t_closest = ang / sw;
      return std::abs(rho - s.r);
    }
    t = (q - s.a).squaredNorm() <= (q - s.b).squaredNorm() ? 0.0 : 1.0;
  }
  if (t_closest) *t_closest = t;
  return (q - point_at(s, t)).norm();
}

double parameter_of(const Segment& s, const Vector2d& p) {
  if (!s.is_arc()) {
    const Vector2d d = s.b - s.a;
    return (p - s.a).dot(d) / d.squaredNorm();
  }
  return travel_angle(s, p - s.c) / std::abs(s.sweep);
}

std::vector<Crossing> intersect(const Segment& s1, const Segment& s2, double tol) {
  if (!s1.is_arc() && !s2.is_arc()) return line_line(s1, s2, tol);
  if (!s1.is_arc()) return line_arc(s1, s2, tol, false);
  if (!s2.is_arc()) return line_arc(s2, s1, tol, true);
  return arc_arc(s1, s2, tol);
}

double signed_area(const std::vector<Segment>& chain) {
  double area = 0;
  for (const auto& s : chain) {
    area += 0.5 * cross(s.a, s.b);
    if (s.is_arc()) area += 0.5 * s.r * s.r * (s.sweep - std::sin(s.sweep));
  }
  return area;
}

double chain_length(const std::vector<Segment>& chain) {
  double L = 0;
  for (const auto& s : chain) L += length(s);
  return L;
}

}  // namespace tf::offset
