// The area a turning wheel section sweeps between two poses (wheel_section.hpp, turning_sweep): the
// sections at both poses and the areas their edges sweep.
#include <algorithm>
#include <cmath>

#include "wheel_section.hpp"

namespace tf::grind::detail {
namespace {

using Polygon = std::vector<Eigen::Vector2d>;

double signed_area(const Polygon& p) {
  double a = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector2d &u = p[i], &v = p[(i + 1) % p.size()];
    a += u.x() * v.y() - u.y() * v.x();
  }
  return 0.5 * a;
}

// Appends p counter-clockwise, unless it has no area.
void add_ccw(Polygon p, std::vector<Polygon>& out) {
  const double a = signed_area(p);
  if (std::abs(a) <= 1e-18) return;
  if (a < 0) std::reverse(p.begin(), p.end());
  out.push_back(std::move(p));
}

// Where segments p q and r s cross (strictly inside both), into x.
bool segments_cross(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r,
                    const Eigen::Vector2d& s, Eigen::Vector2d& x) {
  auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); };
  const Eigen::Vector2d d = q - p, e = s - r;
  const double den = cross(d, e);
  if (std::abs(den) <= 1e-300) return false;
  const double t = cross(r - p, e) / den, u = cross(r - p, d) / den;
  if (!(t > 0 && t < 1 && u > 0 && u < 1)) return false;
  x = p + t * d;
  return true;
}

// The area segment a b sweeps while its ends move straight to a' b' (the turn's arcs taken as chords):
// the quadrilateral a b b' a', or where it crosses itself (the segment turns about a point of itself, or
// its ends' paths cross) the two triangles it bounds.
void add_segment_sweep(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& a1,
                       const Eigen::Vector2d& b1, std::vector<Polygon>& out) {
  Eigen::Vector2d x;
  if (segments_cross(a, b, a1, b1, x)) {
    add_ccw({a, x, a1}, out);
    add_ccw({x, b, b1}, out);
  } else if (segments_cross(a, a1, b, b1, x)) {
    add_ccw({a, b, x}, out);
    add_ccw({x, b1, a1}, out);
  } else {
    add_ccw({a, b, b1, a1}, out);
  }
}

// The hull of `from`, and the sweep of each of its edges whose ends are found in `to`. False when the hull
// is degenerate or none of its edges can be followed.
bool hull_and_edge_sweeps(const Polygon& from, const std::vector<int>& id_from, const Polygon& to,
                          const std::vector<int>& index_to, std::vector<Polygon>& out) {
  const std::vector<int> hull = convex_hull_indices(from);
  if (hull.size() < 3) return false;  // a degenerate section: the caller's hull of both takes it
  Polygon h;
  for (const int i : hull) h.push_back(from[size_t(i)]);
  add_ccw(h, out);
  int followed = 0;
  auto counterpart = [&](int i) {
    const int id = id_from[size_t(i)];
    return id >= 0 && size_t(id) < index_to.size() ? index_to[size_t(id)] : -1;
  };
  for (size_t k = 0; k < hull.size(); ++k) {
    const int ia = hull[k], ib = hull[(k + 1) % hull.size()];
    const int ja = counterpart(ia), jb = counterpart(ib);
    // An end with no counterpart (a ring entering or leaving the plane, a generator moving to the next
    // segment of the profile): the edge lies where the section changes its shape, and the other section's
    // edges, or the sections themselves, cover what it sweeps.
    if (ja < 0 || jb < 0) continue;
    ++followed;
    const Eigen::Vector2d &a = from[size_t(ia)], &b = from[size_t(ib)], &a1 = to[size_t(ja)], &b1 = to[size_t(jb)];
    // An edge whose ends both move into the hull (its outside is on its right) sweeps the side it leaves
    // behind, which the other section's edges sweep outward when followed back.
    const Eigen::Vector2d outward((b - a).y(), -(b - a).x());
    if (outward.dot(a1 - a) <= 0 && outward.dot(b1 - a) <= 0) continue;
    add_segment_sweep(a, b, a1, b1, out);
  }
  return followed > 0;
}

// index[id] = the point of `pts` with that id (-1 for none).
std::vector<int> index_of_ids(const std::vector<int>& ids) {
  int top = -1;
  for (const int id : ids) top = std::max(top, id);
  std::vector<int> index(size_t(top + 1), -1);
  for (size_t i = 0; i < ids.size(); ++i)
    if (ids[i] >= 0) index[size_t(ids[i])] = static_cast<int>(i);
  return index;
}

}  // namespace

bool turning_sweep(const Polygon& p0, const std::vector<int>& id0, const Polygon& p1, const std::vector<int>& id1,
                   std::vector<Polygon>& out) {
  out.clear();
  // Both ways: the edges of either section, followed to the other (a section that changes its shape as
  // the workhead swivels may have edges the other lacks).
  return hull_and_edge_sweeps(p0, id0, p1, index_of_ids(id1), out) &&
         hull_and_edge_sweeps(p1, id1, p0, index_of_ids(id0), out);
}

}  // namespace tf::grind::detail
