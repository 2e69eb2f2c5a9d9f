// Exact sweeps along planar arcs (sweep.hpp: PlanarArc, sweep_arc; sweep_rows.hpp: arc_interval, arc_shadow).
//
// A tool of revolution whose axis lies on lattice axis k, carried without turning along a circular arc in
// the plane across k, sweeps at each height z the points within r(z) of the arc in that plane, r(z) the
// part's cross-section there (a sphere's circle, a cylinder's radius). The points within r of an arc are an
// annular sector (radii rho -+ r) and a disc at each end. A ray along k meets it where r(z) reaches the
// point's distance to the arc; a ray in the plane, at one height, where its line crosses that region. Cut
// between quadrant angles, each piece of the arc is monotone along both axes of the plane, so a line along
// either crosses its region in one interval, whose ends are among the line's crossings of the two circles
// (inside the piece's angles) and of the two end discs. So arcs cost a few pieces per part, not the sub-steps
// their chords would need (a radius 10 mm arc at 0.01 mm: one every 0.89 mm).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "sweep_rows.hpp"
#include "tiltfield/dexel/sweep.hpp"

namespace tf {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kQuarter = kPi / 2.0;

// Is the direction (wu, wv) within the piece's angles [a0, a1] (at most a quarter turn, counter-clockwise)?
bool within(const SweptPart& p, double wu, double wv) {
  const Eigen::Vector4d& e = p.arc_ends;
  return e[0] * wv - e[1] * wu >= 0.0 && wu * e[3] - wv * e[2] >= 0.0;
}

// Distance in the plane from (qu, qv) to the piece.
double arc_distance(const SweptPart& p, double qu, double qv) {
  const double wu = qu - p.arc_cu, wv = qv - p.arc_cv;
  if (within(p, wu, wv)) return std::abs(std::hypot(wu, wv) - p.arc_radius);
  double best = std::numeric_limits<double>::infinity();
  for (int e = 0; e < 4; e += 2)
    best = std::min(best, std::hypot(qu - (p.arc_cu + p.arc_radius * p.arc_ends[e]), qv - (p.arc_cv + p.arc_radius * p.arc_ends[e + 1])));
  return best;
}

// Roots t of |q0 + t e - c|^2 = R^2 for a unit axis direction e (along u when along_u, else along v).
int line_circle(double qu, double qv, bool along_u, double cu, double cv, double R, double t[2]) {
  const double du = qu - cu, dv = qv - cv;
  const double along = along_u ? du : dv, across = along_u ? dv : du;
  const double disc = R * R - across * across;
  if (disc < 0.0) return 0;
  const double sq = std::sqrt(disc);
  t[0] = -along - sq;
  t[1] = -along + sq;
  return 2;
}

// The stretch of the line q0 + t e (e along u or v of the plane) within r of the piece: [t0, t1].
bool arc_line(const SweptPart& p, double qu, double qv, bool along_u, double r, double& t0, double& t1) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  double t[2];
  for (const double R : {p.arc_radius + r, p.arc_radius - r}) {
    if (R <= 0.0) continue;
    const int n = line_circle(qu, qv, along_u, p.arc_cu, p.arc_cv, R, t);
    for (int i = 0; i < n; ++i) {
      const double pu = qu + (along_u ? t[i] : 0.0), pv = qv + (along_u ? 0.0 : t[i]);
      if (!within(p, pu - p.arc_cu, pv - p.arc_cv)) continue;
      lo = std::min(lo, t[i]);
      hi = std::max(hi, t[i]);
    }
  }
  for (int e = 0; e < 4; e += 2) {
    const int n = line_circle(qu, qv, along_u, p.arc_cu + p.arc_radius * p.arc_ends[e], p.arc_cv + p.arc_radius * p.arc_ends[e + 1], r, t);
    for (int i = 0; i < n; ++i) {
      lo = std::min(lo, t[i]);
      hi = std::max(hi, t[i]);
    }
  }
  if (!(hi > lo)) return false;
  t0 = lo;
  t1 = hi;
  return true;
}

// The tip's angle on the circle, in the plane's coordinates.
double angle_of(const PlanarArc& arc, const Eigen::Vector3d& x) {
  const int u = (arc.axis + 1) % 3, v = (arc.axis + 2) % 3;
  return std::atan2(x[v] - arc.center[v], x[u] - arc.center[u]);
}

}  // namespace

bool arc_interval(const SweptPart& p, const Eigen::Vector3d& o, int dir, double& t0, double& t1) {
  const int k = p.arc_axis, u = (k + 1) % 3, v = (k + 2) % 3;
  const bool sphere = p.kind == ToolPart::Kind::Sphere;
  if (dir == k) {  // along the tool's axis: where the cross-section reaches the point's distance to the arc
    const double dist = arc_distance(p, o[u], o[v]);
    if (!(dist < p.radius)) return false;
    if (sphere) {
      const double h = std::sqrt(p.radius * p.radius - dist * dist);
      t0 = p.arc_z0 - h - o[k];
      t1 = p.arc_z0 + h - o[k];
    } else {
      t0 = p.arc_z0 - o[k];
      t1 = p.arc_z1 - o[k];
    }
    return true;
  }
  // In the plane, at the ray's height: the part's cross-section radius there.
  const double z = o[k];
  double r = p.radius;
  if (sphere) {
    const double dz = z - p.arc_z0;
    if (!(std::abs(dz) < p.radius)) return false;
    r = std::sqrt(p.radius * p.radius - dz * dz);
  } else if (z < p.arc_z0 || z > p.arc_z1) {
    return false;
  }
  return arc_line(p, o[u], o[v], dir == u, r, t0, t1);
}

Shadow arc_shadow(const SweptPart& p, int dir, int u) {
  const int v = 3 - dir - u;
  Shadow s;
  if (dir == p.arc_axis) {
    // The piece lies in the triangle of its ends and their tangents' crossing (a quarter turn at most):
    // that triangle grown by the radius holds the region. A row crossing the triangle crosses two of its
    // edges, so the rows' stretches of the three edges' stadiums hold it.
    const double c0 = p.arc_ends[0], s0 = p.arc_ends[1], c1 = p.arc_ends[2], s1 = p.arc_ends[3];
    const double half = 0.5 * (p.arc_a1 - p.arc_a0);
    const double reach = p.arc_radius / std::max(std::cos(half), 1e-12);  // the tangents' crossing, from the centre
    const double cm = std::cos(p.arc_a0 + half), sm = std::sin(p.arc_a0 + half);
    // The plane's (u, v) are the grid's (u, v) or swapped.
    const bool same = u == (p.arc_axis + 1) % 3;
    auto point = [&](double a, double b, double& pu, double& pv) {
      const double x = p.arc_cu + a, y = p.arc_cv + b;
      pu = same ? x : y;
      pv = same ? y : x;
    };
    double e0u, e0v, tu, tv, e1u, e1v;
    point(p.arc_radius * c0, p.arc_radius * s0, e0u, e0v);
    point(reach * cm, reach * sm, tu, tv);
    point(p.arc_radius * c1, p.arc_radius * s1, e1u, e1v);
    s.r = p.radius;
    s.count = 3;
    s.stadiums[0] = make_stadium(e0u, e0v, tu - e0u, tv - e0v);
    s.stadiums[1] = make_stadium(tu, tv, e1u - tu, e1v - tv);
    s.stadiums[2] = make_stadium(e1u, e1v, e0u - e1u, e0v - e1v);
    return s;
  }
  // Across the axis: the box's rectangle in (u, v), by its four edges.
  const double u0 = p.box.min()[u], u1 = p.box.max()[u], v0 = p.box.min()[v], v1 = p.box.max()[v];
  s.r = 0.0;
  s.count = 4;
  s.stadiums[0] = make_stadium(u0, v0, u1 - u0, 0.0);
  s.stadiums[1] = make_stadium(u0, v1, u1 - u0, 0.0);
  s.stadiums[2] = make_stadium(u0, v0, 0.0, v1 - v0);
  s.stadiums[3] = make_stadium(u1, v0, 0.0, v1 - v0);
  return s;
}

bool planar_arc(const PoseAt& pose_at, PlanarArc& arc) {
  ToolPose q[5];
  for (int j = 0; j < 5; ++j) q[j] = pose_at(j / 4.0);
  int k = 0;
  q[0].axis.cwiseAbs().maxCoeff(&k);
  for (const ToolPose& p : q)
    if (std::abs(std::abs(p.axis[k]) - 1.0) > 1e-12 || std::abs(p.tip[k] - q[0].tip[k]) > 1e-9) return false;
  // The circle through the start, middle and end tips, in the plane (u, v).
  const int u = (k + 1) % 3, v = (k + 2) % 3;
  const double ax = q[0].tip[u], ay = q[0].tip[v], bx = q[2].tip[u], by = q[2].tip[v], cx = q[4].tip[u], cy = q[4].tip[v];
  double ux, uy;
  if (std::hypot(cx - ax, cy - ay) < 1e-9) {
    // A full circle: start and end meet; the middle is opposite.
    ux = 0.5 * (ax + bx);
    uy = 0.5 * (ay + by);
  } else {
    const double det = 2.0 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by));
    if (std::abs(det) < 1e-12) return false;  // straight
    const double a2 = ax * ax + ay * ay, b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    ux = (a2 * (by - cy) + b2 * (cy - ay) + c2 * (ay - by)) / det;
    uy = (a2 * (cx - bx) + b2 * (ax - cx) + c2 * (bx - ax)) / det;
  }
  arc.axis = k;
  arc.center = q[0].tip;
  arc.center[u] = ux;
  arc.center[v] = uy;
  arc.radius = std::hypot(ax - ux, ay - uy);
  if (!(arc.radius > 1e-6) || arc.radius > 1e6) return false;
  const double tol = 1e-7 * std::max(1.0, arc.radius);
  for (const ToolPose& p : q)
    if (std::abs(std::hypot(p.tip[u] - ux, p.tip[v] - uy) - arc.radius) > tol) return false;
  // The turn: the quarter point's side tells the direction (counter-clockwise when positive).
  const double a0 = angle_of(arc, q[0].tip), a1 = angle_of(arc, q[1].tip), a4 = angle_of(arc, q[4].tip);
  const bool ccw = std::remainder(a1 - a0, 2.0 * kPi) > 0.0;
  double turn = a4 - a0;
  if (ccw) {
    while (turn <= 1e-12) turn += 2.0 * kPi;
  } else {
    while (turn >= -1e-12) turn -= 2.0 * kPi;
  }
  arc.a0 = a0;
  arc.sweep = turn;
  // The other quarter points must lie on the same turn, at a quarter and three quarters of it.
  for (int j = 1; j < 4; ++j)
    if (std::abs(std::remainder(angle_of(arc, q[j].tip) - (a0 + turn * j / 4.0), 2.0 * kPi)) > 1e-6) return false;
  return true;
}

void sweep_arc(const PlanarArc& arc, const ToolPose& pose0, const std::vector<ToolPart>& parts, BlockSweep& out) {
  const int k = arc.axis, u = (k + 1) % 3, v = (k + 2) % 3;
  const Eigen::Vector3d axis = pose0.axis.normalized(), ref = axis.unitOrthogonal();
  // The turn counter-clockwise, cut at quadrant angles.
  const double b0 = arc.sweep >= 0.0 ? arc.a0 : arc.a0 + arc.sweep, b1 = b0 + std::abs(arc.sweep);
  std::vector<std::pair<double, double>> pieces;
  for (double a = b0; a < b1 - 1e-12;) {
    const double next = std::min(b1, (std::floor(a / kQuarter + 1e-9) + 1.0) * kQuarter);
    if (next > a + 1e-12) pieces.push_back({a, next});
    a = next;
  }
  for (int pass = 0; pass < 2; ++pass)
    for (const ToolPart& part : parts) {
      if (part.cutting != (pass == 0)) continue;
      // The part's reference point at the start: the arc it follows is the tip's, moved by the same offset.
      const Eigen::Vector3d side = ref * std::cos(part.angle) + axis.cross(ref) * std::sin(part.angle);
      const Eigen::Vector3d offset = part.h0 * axis + part.offset * side;
      for (const auto& [a0, a1] : pieces) {
        SweptPart s;
        s.kind = part.kind;
        s.arc = true;
        s.arc_axis = k;
        s.axis = axis;
        s.radius = part.radius;
        s.component = part.component;
        s.cutting = part.cutting;
        s.arc_cu = arc.center[u] + offset[u];
        s.arc_cv = arc.center[v] + offset[v];
        s.arc_radius = arc.radius;
        s.arc_a0 = a0;
        s.arc_a1 = a1;
        s.arc_ends = Eigen::Vector4d(std::cos(a0), std::sin(a0), std::cos(a1), std::sin(a1));
        const double z0 = arc.center[k] + offset[k];
        if (part.kind == ToolPart::Kind::Sphere) {
          s.arc_z0 = s.arc_z1 = z0;
        } else {
          const double z1 = z0 + (part.h1 - part.h0) * axis[k];
          s.arc_z0 = std::min(z0, z1);
          s.arc_z1 = std::max(z0, z1);
          s.height = part.h1 - part.h0;
        }
        // The piece's ends bound it along both plane axes (it turns at most a quarter between quadrant angles).
        Eigen::Vector3d lo, hi;
        const double eu0 = s.arc_cu + arc.radius * std::cos(a0), eu1 = s.arc_cu + arc.radius * std::cos(a1);
        const double ev0 = s.arc_cv + arc.radius * std::sin(a0), ev1 = s.arc_cv + arc.radius * std::sin(a1);
        lo[u] = std::min(eu0, eu1) - s.radius;
        hi[u] = std::max(eu0, eu1) + s.radius;
        lo[v] = std::min(ev0, ev1) - s.radius;
        hi[v] = std::max(ev0, ev1) + s.radius;
        lo[k] = part.kind == ToolPart::Kind::Sphere ? s.arc_z0 - s.radius : s.arc_z0;
        hi[k] = part.kind == ToolPart::Kind::Sphere ? s.arc_z0 + s.radius : s.arc_z1;
        s.p0 = 0.5 * (lo + hi);
        s.box = Eigen::AlignedBox3d(lo, hi);
        out.parts.push_back(s);
        out.box.extend(s.box);
      }
      if (part.cutting) out.swept_parts_cutting = static_cast<int>(out.parts.size());
    }
  out.substeps = 1;
  out.cutting_error = out.holder_error = 0.0;
  out.tip_length = arc.radius * std::abs(arc.sweep);
}

}  // namespace tf
