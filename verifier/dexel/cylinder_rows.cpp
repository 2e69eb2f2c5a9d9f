// The swept cylinder against a row of parallel lattice rays, in one batch: the innermost loop of 5-axis
// verification, where flutes, shank and holder segments are tilted cylinders over many sub-steps.
//
// Same method as the scalar cylinder_interval (sweep.cpp): the ray o + t e meets the cylinder swept by d
// where some s in [0, 1] puts o + t e - s d inside the cylinder, a convex set in (t, s) bounded by one
// quadratic Q (the radius) and four linear constraints (0 <= axial <= H, 0 <= s <= 1). The extremes of t
// are among fourteen candidates: the four corners of the linear constraints, the roots of Q on each of
// their four lines, and the two points of Q with a tangent along s. Here every candidate is computed for
// every ray and kept or dropped by a select, so the loop has no branches and vectorises (row_kernels.hpp,
// and verifier/CMakeLists.txt for the flags). Rows where the candidates' coefficients degenerate (the ray
// across the axis, or the motion along it) go to the scalar enumeration.
#include <cmath>
#include <limits>

#include "row_kernels.hpp"
#include "sweep_rows.hpp"

namespace tf {
namespace {

using row_kernels::kInf;

// Per row: Q(t, s) = A t^2 + 2B ts + C s^2 + 2D t + 2E s + F, D, E and F linear / quadratic along the row
// through the ray's offset pw from the axis; axial coordinate aw + t ae - s ad.
struct CylRow {
  double A, B, C, ae, ad, H, eps_l, eps_q, r2;
  double pw0[3], pwu[3];  // offset from the axis of the first ray, and its change per ray (perp. to the axis)
  double pe[3], pd[3];    // the ray direction and the motion, perpendicular to the axis
  double aw0, awu;        // axial coordinate of the first ray's origin, and its change per ray
  double inv_ae, inv_C;
  double kz, qa_z;        // on the axial lines t = kz s + c: Q's s^2 coefficient
  double qa_tan;          // on the tangency line s = -(B t + E) / C: Q's t^2 coefficient
  double inv_A, inv_qa_z, inv_qa_tan;
  double shift;           // t from the row's origin = t from the plane through p0 + shift
};

struct Roots {
  double x0, x1;
  bool ok;
};

// Roots of qa x^2 + 2 qb x + qc, inv_qa = 1 / qa (a row's constant: one division less per ray; qa may be 0:
// then x1 is the linear root and x0 is not finite).
[[gnu::always_inline]] inline Roots roots(double qa, double inv_qa, double qb, double qc) {
  double disc = qb * qb - qa * qc;
  const bool ok = disc >= -1e-12 * (qb * qb + std::abs(qa * qc));
  disc = disc > 0.0 ? disc : 0.0;
  const double sq = std::sqrt(disc);
  const double q = -(qb + (qb >= 0.0 ? sq : -sq));
  const double x0 = q * inv_qa;
  const double x1 = q != 0.0 ? qc / q : x0;
  return {x0, x1, ok};
}

[[gnu::always_inline]] inline void cylinder_lane(const CylRow& k, int i, double& t0, double& t1) {
  const double pw0 = k.pw0[0] + i * k.pwu[0], pw1 = k.pw0[1] + i * k.pwu[1], pw2 = k.pw0[2] + i * k.pwu[2];
  const double D = k.pe[0] * pw0 + k.pe[1] * pw1 + k.pe[2] * pw2;
  const double E = -(k.pd[0] * pw0 + k.pd[1] * pw1 + k.pd[2] * pw2);
  const double F = pw0 * pw0 + pw1 * pw1 + pw2 * pw2 - k.r2;
  const double aw = k.aw0 + i * k.awu;
  // The helpers are forced inline: the target clones would otherwise call them and not vectorise.
  auto Q = [&](double t, double s) __attribute__((always_inline)) { return k.A * t * t + 2 * k.B * t * s + k.C * s * s + 2 * D * t + 2 * E * s + F; };
  auto linear_ok = [&](double t, double s) __attribute__((always_inline)) {
    const double z = aw + t * k.ae - s * k.ad;
    return (z >= -k.eps_l) & (z <= k.H + k.eps_l) & (s >= -k.eps_l) & (s <= 1.0 + k.eps_l);
  };
  double lo = kInf, hi = -kInf;
  auto take = [&](bool ok, double t) __attribute__((always_inline)) {
    const double a = ok ? t : kInf, b = ok ? t : -kInf;
    lo = a < lo ? a : lo;
    hi = b > hi ? b : hi;
  };
  // (a) The corners: axial 0 or H, s = 0 or 1 (the linear constraints hold there; Q must too).
#pragma GCC unroll 4
  for (int c = 0; c < 4; ++c) {
    const double z = (c & 1) ? k.H : 0.0, s = (c & 2) ? 1.0 : 0.0;
    const double t = (z - aw + k.ad * s) * k.inv_ae;
    take(Q(t, s) <= k.eps_q, t);
  }
  // (b) Q = 0 on the lines s = 0 and s = 1 ...
#pragma GCC unroll 2
  for (int c = 0; c < 2; ++c) {
    const double s = c;
    const Roots r = roots(k.A, k.inv_A, k.B * s + D, k.C * s * s + 2 * E * s + F);
    take(r.ok & linear_ok(r.x0, s), r.x0);
    take(r.ok & linear_ok(r.x1, s), r.x1);
  }
  // ... and on the axial lines z = 0 and z = H: t = kz s + c.
#pragma GCC unroll 2
  for (int c = 0; c < 2; ++c) {
    const double cz = ((c ? k.H : 0.0) - aw) * k.inv_ae;
    const Roots r = roots(k.qa_z, k.inv_qa_z, k.A * k.kz * cz + k.B * cz + D * k.kz + E, k.A * cz * cz + 2 * D * cz + F);
    const double ta = k.kz * r.x0 + cz, tb = k.kz * r.x1 + cz;
    take(r.ok & linear_ok(ta, r.x0), ta);
    take(r.ok & linear_ok(tb, r.x1), tb);
  }
  // (c) Q = 0 with dQ/ds = 0: s = -(B t + E) / C.
  {
    const Roots r = roots(k.qa_tan, k.inv_qa_tan, D - k.B * E * k.inv_C, F - E * E * k.inv_C);
    const double sa = -(k.B * r.x0 + E) * k.inv_C, sb = -(k.B * r.x1 + E) * k.inv_C;
    take(r.ok & linear_ok(r.x0, sa), r.x0);
    take(r.ok & linear_ok(r.x1, sb), r.x1);
  }
  const bool hit = hi > lo;
  t0 = hit ? lo + k.shift : kInf;
  t1 = hit ? hi + k.shift : -kInf;
}

TF_VECTOR_CLONES
void cylinder_row(const CylRow& row, int n, double* __restrict t0, double* __restrict t1) {
  // A local copy: its fields may be read under a select without a masked load (which stops the vectoriser).
  const CylRow k = row;
  row_kernels::in_blocks(n, t0, t1, [&](int i, double& a, double& b) __attribute__((always_inline)) {
    cylinder_lane(k, i, a, b);
  });
}

}  // namespace

namespace {

// A cylinder that does not move (the exact end poses of a block whose axis turns): per ray, the chord of
// the infinite cylinder (a quadratic in t) within the slab between its end planes.
void static_cylinder_row(const SweptPart& p, const Eigen::Vector3d& o, int dir, int u, double step, int n, double* t0,
                         double* t1) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const Eigen::Vector3d& a = p.axis;
  auto perp = [&](const Eigen::Vector3d& x) -> Eigen::Vector3d { return x - a * a.dot(x); };
  Eigen::Vector3d e = Eigen::Vector3d::Zero(), eu = Eigen::Vector3d::Zero();
  e[dir] = 1.0;
  eu[u] = step;
  const Eigen::Vector3d pe = perp(e);
  const double A = pe.squaredNorm(), ae = a[dir], r2 = p.radius * p.radius;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d w = o + double(i) * eu - p.p0;
    double lo = -kInf, hi = kInf;
    const Eigen::Vector3d pw = perp(w);
    const double B = pw.dot(pe), C = pw.squaredNorm() - r2;
    if (A > 1e-12) {
      const double disc = B * B - A * C;
      if (disc > 0.0) {
        const double s = std::sqrt(disc);
        lo = (-B - s) / A, hi = (-B + s) / A;
      } else {
        lo = kInf, hi = -kInf;
      }
    } else if (C > 0.0) {
      lo = kInf, hi = -kInf;  // along the axis, outside the radius
    }
    const double aw = a.dot(w);
    if (std::abs(ae) > 1e-12) {
      const double s0 = -aw / ae, s1 = (p.height - aw) / ae;
      lo = std::max(lo, std::min(s0, s1)), hi = std::min(hi, std::max(s0, s1));
    } else if (aw < 0.0 || aw > p.height) {
      lo = kInf, hi = -kInf;
    }
    const bool hit = hi > lo;
    t0[i] = hit ? lo : kInf;
    t1[i] = hit ? hi : -kInf;
  }
}

}  // namespace

bool cylinder_intervals(const SweptPart& p, const Eigen::Vector3d& o, int dir, int u, double step, int n, double* t0,
                        double* t1) {
  if (p.d.squaredNorm() == 0.0) {
    static_cylinder_row(p, o, dir, u, step, n, t0, t1);
    return true;
  }
  const Eigen::Vector3d& a = p.axis;
  auto perp = [&](const Eigen::Vector3d& x) -> Eigen::Vector3d { return x - a * a.dot(x); };
  Eigen::Vector3d e = Eigen::Vector3d::Zero(), eu = Eigen::Vector3d::Zero();
  e[dir] = 1.0;
  eu[u] = step;
  CylRow k;
  k.ae = a[dir];
  const Eigen::Vector3d pe = perp(e), pd = perp(p.d);
  k.A = pe.squaredNorm();
  k.B = -pe.dot(pd);
  k.C = pd.squaredNorm();
  // The degenerate rows: the ray across the axis (no corners in t), the motion along it (no tangency).
  if (std::abs(k.ae) < 1e-9 || k.C < 1e-12 * (1.0 + p.d.squaredNorm())) return false;
  k.ad = a.dot(p.d);
  k.H = p.height;
  k.r2 = p.radius * p.radius;
  k.eps_l = 1e-9;
  k.eps_q = 1e-9 * (k.r2 + 1.0);
  // Origins moved along the ray into the plane through p0 across it: coefficients of the order of the tool.
  Eigen::Vector3d w = o - p.p0;
  k.shift = -w[dir];
  w[dir] = 0.0;
  const Eigen::Vector3d pw = perp(w), pu = perp(eu);
  for (int c = 0; c < 3; ++c) {
    k.pw0[c] = pw[c];
    k.pwu[c] = pu[c];
    k.pe[c] = pe[c];
    k.pd[c] = pd[c];
  }
  k.aw0 = a.dot(w);
  k.awu = a.dot(eu);
  k.inv_ae = 1.0 / k.ae;
  k.inv_C = 1.0 / k.C;
  k.kz = k.ad * k.inv_ae;
  k.qa_z = k.A * k.kz * k.kz + 2 * k.B * k.kz + k.C;
  k.qa_tan = k.A - k.B * k.B * k.inv_C;
  k.inv_A = 1.0 / k.A;
  k.inv_qa_z = 1.0 / k.qa_z;
  k.inv_qa_tan = 1.0 / k.qa_tan;
  cylinder_row(k, n, t0, t1);
  return true;
}

}  // namespace tf
