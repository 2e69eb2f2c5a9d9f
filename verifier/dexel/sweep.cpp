#include "tiltfield/dexel/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "sweep_rows.hpp"

namespace tf {

std::vector<ToolPart> tool_parts(const Tool& tool, const SweepOptions& options) {
  std::vector<ToolPart> parts;
  const double R = tool.radius();
  auto cylinder = [&](double h0, double h1, double r, ToolComponent c, bool cutting) {
    if (h1 > h0 + 1e-12 && r > 0) parts.push_back({ToolPart::Kind::Cylinder, h0, h1, r, 0.0, 0.0, c, cutting});
  };
  if (std::holds_alternative<BallCutter>(tool.cutter)) {
    parts.push_back({ToolPart::Kind::Sphere, R, 0.0, R, 0.0, 0.0, ToolComponent::Ball, true});
    cylinder(R, tool.flute_length, R, ToolComponent::Flute, true);
  } else if (std::holds_alternative<FlatCutter>(tool.cutter)) {
    // The end face region (up to one radius) is reported as the end form ("ball"), the rest as flutes.
    const double end = std::min(tool.flute_length, R);
    cylinder(0.0, end, R, ToolComponent::Ball, true);
    cylinder(end, tool.flute_length, R, ToolComponent::Flute, true);
  } else {
    const auto& b = std::get<BullCutter>(tool.cutter);
    const double rc = b.corner_radius, rho = b.radius - b.corner_radius;
    if (rho <= 1e-9) {
      parts.push_back({ToolPart::Kind::Sphere, rc, 0.0, rc, 0.0, 0.0, ToolComponent::Ball, true});
    } else {
      cylinder(0.0, rc, rho, ToolComponent::Ball, true);
      // Ring of spheres on the torus' centre circle; the lens between neighbours at spacing delta is
      // rc - sqrt(rc^2 - delta^2/4) deep, kept below torus_tolerance.
      const double tol = std::clamp(options.torus_tolerance, 1e-6, rc);
      const double delta = 2.0 * std::sqrt(std::max(0.0, rc * rc - (rc - tol) * (rc - tol)));
      const int n = std::max(8, static_cast<int>(std::ceil(2.0 * std::numbers::pi * rho / delta)));
      for (int i = 0; i < n; ++i)
        parts.push_back({ToolPart::Kind::Sphere, rc, 0.0, rc, rho, 2.0 * std::numbers::pi * i / n, ToolComponent::Ball, true});
    }
    cylinder(rc, tool.flute_length, R, ToolComponent::Flute, true);
  }
  cylinder(tool.flute_length, tool.length, tool.shank_radius, ToolComponent::Shank, false);
  double h = tool.length;
  for (const auto& s : tool.holder) {
    cylinder(h, h + s.length, s.radius, ToolComponent::Holder, false);
    h += s.length;
  }
  return parts;
}

SweptPart sweep_part(const ToolPart& part, const Eigen::Vector3d& tip, const Eigen::Vector3d& axis,
                     const Eigen::Vector3d& ref, const Eigen::Vector3d& d) {
  SweptPart s;
  s.kind = part.kind;
  s.d = d;
  s.axis = axis;
  s.radius = part.radius;
  s.component = part.component;
  s.cutting = part.cutting;
  if (part.kind == ToolPart::Kind::Sphere) {
    const Eigen::Vector3d side = ref * std::cos(part.angle) + axis.cross(ref) * std::sin(part.angle);
    s.p0 = tip + part.h0 * axis + part.offset * side;
    const Eigen::Vector3d r = Eigen::Vector3d::Constant(part.radius);
    s.box = Eigen::AlignedBox3d(s.p0 - r, s.p0 + r);
    const double dd = d.squaredNorm();
    if (dd > 1e-24) {
      s.len = std::sqrt(dd);
      s.inv_len = 1.0 / s.len;
      for (int k = 0; k < 3; ++k) {
        const double de = d[k] * s.inv_len, a = 1.0 - de * de;
        s.dir_cos[k] = de;
        s.inv_sin2[k] = a > 1e-14 ? 1.0 / a : 0.0;
        s.inv_cos[k] = std::abs(de) > 1e-14 ? 1.0 / de : 0.0;
      }
    }
    s.box.extend(s.p0 + d - r);
    s.box.extend(s.p0 + d + r);
  } else {
    s.p0 = tip + part.h0 * axis;
    s.height = part.h1 - part.h0;
    // A disc of radius r with normal a spans r * sqrt(1 - a_k^2) along axis k.
    const Eigen::Vector3d ext = (Eigen::Vector3d::Ones() - axis.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt() * part.radius;
    const Eigen::Vector3d p1 = s.p0 + s.height * axis;
    s.box = Eigen::AlignedBox3d(s.p0 - ext, s.p0 + ext);
    s.box.extend(p1 - ext);
    s.box.extend(p1 + ext);
    s.box.extend(s.p0 + d - ext);
    s.box.extend(s.p0 + d + ext);
    s.box.extend(p1 + d - ext);
    s.box.extend(p1 + d + ext);
  }
  return s;
}

namespace {

// Real roots of qa x^2 + qb x + qc = 0 (a double root once); returns the count.
int solve_quadratic(double qa, double qb, double qc, double& x0, double& x1) {
  const double scale = std::abs(qa) + std::abs(qb) + std::abs(qc);
  if (scale == 0.0) return 0;
  if (std::abs(qa) <= 1e-14 * scale) {
    if (std::abs(qb) <= 1e-14 * scale) return 0;
    x0 = -qc / qb;
    return 1;
  }
  double disc = qb * qb - 4.0 * qa * qc;
  if (disc < 0.0) {
    if (disc < -1e-12 * (qb * qb + std::abs(4.0 * qa * qc))) return 0;
    disc = 0.0;
  }
  const double sq = std::sqrt(disc);
  // Numerically stable pair.
  const double q = -0.5 * (qb + (qb >= 0 ? sq : -sq));
  if (q == 0.0) {
    x0 = x1 = 0.0;
    return 1;
  }
  x0 = q / qa;
  x1 = qc / q;
  return 2;
}

// The t-extent of {(t, s): Q(t, s) <= 0, lin_k(t, s) <= c_k}, Q convex, by enumerating the points where
// the extremes can be: two linear constraints active, one linear and Q, or Q alone with dQ/ds = 0.
struct Region {
  double A, B, C, D, E, F;  // Q = A t^2 + 2B ts + C s^2 + 2D t + 2E s + F
  double la[4], lb[4], lc[4];
  int nl = 0;
  double eps_l = 1e-9, eps_q = 1e-9;

  double q(double t, double s) const { return A * t * t + 2 * B * t * s + C * s * s + 2 * D * t + 2 * E * s + F; }
  bool feasible(double t, double s, int skip0 = -1, int skip1 = -1) const {
    for (int k = 0; k < nl; ++k)
      if (k != skip0 && k != skip1 && la[k] * t + lb[k] * s > lc[k] + eps_l) return false;
    return true;
  }
  void take(double t, double& lo, double& hi) const {
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }

  bool extent(double& t0, double& t1) const {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    // (a) vertices of the linear constraints.
    for (int i = 0; i < nl; ++i)
      for (int j = i + 1; j < nl; ++j) {
        const double det = la[i] * lb[j] - la[j] * lb[i];
        if (std::abs(det) < 1e-14) continue;
        const double t = (lc[i] * lb[j] - lc[j] * lb[i]) / det, s = (la[i] * lc[j] - la[j] * lc[i]) / det;
        if (q(t, s) <= eps_q && feasible(t, s, i, j)) take(t, lo, hi);
      }
    // (b) Q = 0 on each linear constraint's line.
    for (int k = 0; k < nl; ++k) {
      double r0 = 0, r1 = 0;
      if (std::abs(lb[k]) >= std::abs(la[k])) {
        if (lb[k] == 0.0) continue;
        const double s0 = lc[k] / lb[k], s1 = -la[k] / lb[k];
        const int n = solve_quadratic(A + 2 * B * s1 + C * s1 * s1, 2 * (B * s0 + C * s0 * s1 + D + E * s1),
                                      C * s0 * s0 + 2 * E * s0 + F, r0, r1);
        if (n >= 1 && feasible(r0, s0 + s1 * r0, k)) take(r0, lo, hi);
        if (n >= 2 && feasible(r1, s0 + s1 * r1, k)) take(r1, lo, hi);
      } else {
        const double t0_ = lc[k] / la[k], t1_ = -lb[k] / la[k];
        const int n = solve_quadratic(A * t1_ * t1_ + 2 * B * t1_ + C, 2 * (A * t0_ * t1_ + B * t0_ + D * t1_ + E),
                                      A * t0_ * t0_ + 2 * D * t0_ + F, r0, r1);
        if (n >= 1 && feasible(t0_ + t1_ * r0, r0, k)) take(t0_ + t1_ * r0, lo, hi);
        if (n >= 2 && feasible(t0_ + t1_ * r1, r1, k)) take(t0_ + t1_ * r1, lo, hi);
      }
    }
    // (c) Q alone: the points of Q = 0 with a tangent along s.
    const double scale = std::abs(A) + std::abs(C) + 1e-300;
    if (C > 1e-12 * scale) {
      double r0 = 0, r1 = 0;
      const int n = solve_quadratic(A - B * B / C, 2 * (D - B * E / C), F - E * E / C, r0, r1);
      for (int i = 0; i < n; ++i) {
        const double t = i ? r1 : r0, s = -(B * t + E) / C;
        if (feasible(t, s)) take(t, lo, hi);
      }
    } else {
      // Q does not depend on s: its roots in t, at any s the linear constraints allow.
      double r0 = 0, r1 = 0;
      const int n = solve_quadratic(A, 2 * D, F, r0, r1);
      for (int i = 0; i < n; ++i) {
        const double t = i ? r1 : r0;
        double slo = -std::numeric_limits<double>::infinity(), shi = -slo;
        bool ok = true;
        for (int k = 0; k < nl && ok; ++k) {
          if (std::abs(lb[k]) < 1e-14) { ok = la[k] * t <= lc[k] + eps_l; continue; }
          const double b = (lc[k] - la[k] * t) / lb[k];
          if (lb[k] > 0) shi = std::min(shi, b); else slo = std::max(slo, b);
        }
        if (ok && slo <= shi + eps_l) take(t, lo, hi);
      }
    }
    if (!(hi > lo)) return false;
    t0 = lo;
    t1 = hi;
    return true;
  }
};

bool cylinder_interval(const SweptPart& p, const Eigen::Vector3d& o, const Eigen::Vector3d& e, double& t0, double& t1) {
  const Eigen::Vector3d& a = p.axis;
  const Eigen::Vector3d w = o - p.p0;
  auto perp = [&](const Eigen::Vector3d& x) -> Eigen::Vector3d { return x - a * a.dot(x); };
  const Eigen::Vector3d pw = perp(w), pe = perp(e), pd = perp(p.d);
  Region g;
  g.A = pe.squaredNorm();
  g.B = -pe.dot(pd);
  g.C = pd.squaredNorm();
  g.D = pe.dot(pw);
  g.E = -pd.dot(pw);
  g.F = pw.squaredNorm() - p.radius * p.radius;
  g.eps_q = 1e-9 * (p.radius * p.radius + 1.0);
  const double ae = a.dot(e), ad = a.dot(p.d), aw = a.dot(w);
  // 0 <= aw + t ae - s ad <= H, 0 <= s <= 1.
  g.la[0] = -ae; g.lb[0] = ad;  g.lc[0] = aw;
  g.la[1] = ae;  g.lb[1] = -ad; g.lc[1] = p.height - aw;
  g.la[2] = 0;   g.lb[2] = -1;  g.lc[2] = 0;
  g.la[3] = 0;   g.lb[3] = 1;   g.lc[3] = 1;
  g.nl = 4;
  return g.extent(t0, t1);
}

}  // namespace

bool ray_interval(const SweptPart& part, const Eigen::Vector3d& o, int dir, double& t0, double& t1) {
  if (part.arc) return arc_interval(part, o, dir, t0, t1);
  if (part.kind == ToolPart::Kind::Cylinder) {
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e[dir] = 1.0;
    return cylinder_interval(part, o, e, t0, t1);
  }
  double a = 0.0, b = 0.0;
  ray_intervals(part, o, dir, (dir + 1) % 3, 0.0, 1, &a, &b);
  if (!(b > a)) return false;
  t0 = a;
  t1 = b;
  return true;
}

void ray_intervals(const SweptPart& part, const Eigen::Vector3d& o, int dir, int u, double step, int n, double* t0,
                   double* t1) {
  if (part.arc) {  // arc pieces ray by ray (a block has a few)
    Eigen::Vector3d x = o;
    for (int i = 0; i < n; ++i) {
      x[u] = o[u] + step * i;
      if (!arc_interval(part, x, dir, t0[i], t1[i])) {
        t0[i] = std::numeric_limits<double>::infinity();
        t1[i] = -t0[i];
      }
    }
    return;
  }
  if (part.kind == ToolPart::Kind::Sphere) {
    capsule_intervals(part, o, dir, u, step, n, t0, t1);
    return;
  }
  if (cylinder_intervals(part, o, dir, u, step, n, t0, t1)) return;
  Eigen::Vector3d e = Eigen::Vector3d::Zero(), x = o;
  e[dir] = 1.0;
  for (int i = 0; i < n; ++i) {
    x[u] = o[u] + step * i;
    if (!cylinder_interval(part, x, e, t0[i], t1[i])) {
      t0[i] = std::numeric_limits<double>::infinity();
      t1[i] = -t0[i];
    }
  }
}

Joints interpolate_block(const Joints& from, const Block& b, double tau) {
  Joints j;
  const Joints& to = b.target;
  j.x = from.x + tau * (to.x - from.x);
  j.y = from.y + tau * (to.y - from.y);
  j.z = from.z + tau * (to.z - from.z);
  j.a = from.a + tau * (to.a - from.a);
  j.b = from.b + tau * (to.b - from.b);
  j.c = from.c + tau * (to.c - from.c);
  if (b.motion == Motion::ArcCW || b.motion == Motion::ArcCCW) {
    int iu = 0, iv = 1;
    if (b.plane == 18) { iu = 2; iv = 0; }
    if (b.plane == 19) { iu = 1; iv = 2; }
    const Eigen::Vector3d s(from.x, from.y, from.z), e(to.x, to.y, to.z), c = b.arc_center;
    const double as = std::atan2(s[iv] - c[iv], s[iu] - c[iu]), ae = std::atan2(e[iv] - c[iv], e[iu] - c[iu]);
    const double rs = std::hypot(s[iu] - c[iu], s[iv] - c[iv]), re = std::hypot(e[iu] - c[iu], e[iv] - c[iv]);
    const double two_pi = 2.0 * std::numbers::pi;
    double sweep = b.motion == Motion::ArcCCW ? ae - as : as - ae;
    sweep = std::fmod(sweep + 2.0 * two_pi, two_pi);
    if (sweep < 1e-9) sweep = two_pi;  // same start and end: a full circle
    const double ang = as + (b.motion == Motion::ArcCCW ? 1.0 : -1.0) * tau * sweep;
    const double r = rs + tau * (re - rs);
    Eigen::Vector3d p(j.x, j.y, j.z);
    p[iu] = c[iu] + r * std::cos(ang);
    p[iv] = c[iv] + r * std::sin(ang);
    j.x = p.x();
    j.y = p.y();
    j.z = p.z();
  }
  return j;
}

}  // namespace tf
