// The shadows of swept parts along a grid axis (sweep.hpp: Shadow), row by row and for a tile's rows in
// one batch: branch-free per row (row_kernels.hpp), since the verifier asks it for every row of every
// tile a part covers.
#include <algorithm>
#include <cmath>

#include "row_kernels.hpp"
#include "sweep_rows.hpp"

namespace tf {
namespace {

using row_kernels::kInf;


// Widens [lo, hi] by the stretch of the line {v = cv} within r of the segment s; selects only.
[[gnu::always_inline]] inline void stadium_row(const Shadow::Stadium& s, double r, double cv, double& lo, double& hi) {
  const double r2 = r * r;
  // The discs about the two ends.
  const double o0 = cv - s.pv, o1 = o0 - s.dv;
  const double e0 = r2 - o0 * o0, e1 = r2 - o1 * o1;
  const double q0 = std::sqrt(e0 > 0.0 ? e0 : 0.0), q1 = std::sqrt(e1 > 0.0 ? e1 : 0.0);
  const double lo0 = e0 >= 0.0 ? s.pu - q0 : kInf, hi0 = e0 >= 0.0 ? s.pu + q0 : -kInf;
  const double lo1 = e1 >= 0.0 ? s.pu + s.du - q1 : kInf, hi1 = e1 >= 0.0 ? s.pu + s.du + q1 : -kInf;
  lo = lo0 < lo ? lo0 : lo;
  lo = lo1 < lo ? lo1 : lo;
  hi = hi0 > hi ? hi0 : hi;
  hi = hi1 > hi ? hi1 : hi;
  // The band between them: within r of the segment's line (|n . x| <= r, n = (-tv, tu)) and between
  // the end normals (0 <= t . x <= len), x = (u - pu, cv - pv): two linear conditions on x_u, each
  // lo_c <= coef x_u + off <= hi_c (with inv = 1 / coef, 0 when coef is 0: then a condition on off).
  double a = -kInf, b = kInf;
  auto clip = [&](double coef, double inv, double off, double lo_c, double hi_c) __attribute__((always_inline)) {
    const double x0 = (lo_c - off) * inv, x1 = (hi_c - off) * inv;
    const double xa = coef < 0.0 ? x1 : x0, xb = coef < 0.0 ? x0 : x1;
    const bool none = (inv == 0.0) & ((off < lo_c) | (off > hi_c));
    a = inv == 0.0 ? a : (xa > a ? xa : a);
    b = inv == 0.0 ? b : (xb < b ? xb : b);
    a = none ? kInf : a;
  };
  clip(-s.tv, -s.inv_tv, s.tu * o0, -r, r);
  clip(s.tu, s.inv_tu, s.tv * o0, 0.0, s.len);
  const bool band = (s.len > 1e-12) & (a <= b);
  const double la = band ? s.pu + a : kInf, hb = band ? s.pu + b : -kInf;
  lo = la < lo ? la : lo;
  hi = hb > hi ? hb : hi;
}

template <int kCount>
[[gnu::always_inline]] inline void shadow_lane(const Shadow& s, double cv, double& lo, double& hi) {
  lo = kInf;
  hi = -kInf;
#pragma GCC unroll 4
  for (int i = 0; i < kCount; ++i) stadium_row(s.stadiums[i], s.r, cv, lo, hi);
  // A margin well below any length the lattice resolves, against rounding at tangent rays.
  lo -= 1e-9;
  hi += 1e-9;
}

TF_VECTOR_CLONES
void shadow_batch(const Shadow& shadow, double cv0, double step, int n, double* lo, double* hi) {
  const Shadow s = shadow;  // a local copy: read under selects without masked loads (cylinder_rows.cpp)
  if (s.count == 1)
    row_kernels::in_blocks(n, lo, hi, [&](int i, double& a, double& b) __attribute__((always_inline)) {
      shadow_lane<1>(s, cv0 + step * i, a, b);
    });
  else
    row_kernels::in_blocks(n, lo, hi, [&](int i, double& a, double& b) __attribute__((always_inline)) {
      shadow_lane<4>(s, cv0 + step * i, a, b);
    });
}

}  // namespace

Shadow::Stadium make_stadium(double pu, double pv, double du, double dv) {
  Shadow::Stadium s;
  s.pu = pu;
  s.pv = pv;
  s.du = du;
  s.dv = dv;
  s.len = std::sqrt(du * du + dv * dv);
  if (s.len > 1e-12) {
    s.tu = du / s.len;
    s.tv = dv / s.len;
    s.inv_tu = std::abs(s.tu) > 1e-15 ? 1.0 / s.tu : 0.0;
    s.inv_tv = std::abs(s.tv) > 1e-15 ? 1.0 / s.tv : 0.0;
  }
  return s;
}

Shadow make_shadow(const SweptPart& part, int dir, int u) {
  if (part.arc) return arc_shadow(part, dir, u);
  const int v = 3 - dir - u;
  Shadow s;
  s.r = part.radius;
  const double pu = part.p0[u], pv = part.p0[v], du = part.d[u], dv = part.d[v];
  if (part.kind == ToolPart::Kind::Sphere || std::abs(part.axis[dir]) >= 1.0 - 1e-12) {
    s.count = 1;
    s.stadiums[0] = make_stadium(pu, pv, du, dv);
    // A cylinder taken as along the ray: its top disc may still lie off its bottom across the ray.
    if (part.kind == ToolPart::Kind::Cylinder) s.r += part.height * std::hypot(part.axis[u], part.axis[v]);
    return s;
  }
  // The parallelogram p0 + [0, 1] axis H + [0, 1] d, by its four edges.
  const double au = part.axis[u] * part.height, av = part.axis[v] * part.height;
  s.count = 4;
  s.stadiums[0] = make_stadium(pu, pv, du, dv);
  s.stadiums[1] = make_stadium(pu + au, pv + av, du, dv);
  s.stadiums[2] = make_stadium(pu, pv, au, av);
  s.stadiums[3] = make_stadium(pu + du, pv + dv, au, av);
  return s;
}

bool shadow_row(const Shadow& s, double cv, double& lo, double& hi) {
  shadow_batch(s, cv, 0.0, 1, &lo, &hi);
  return hi >= lo;
}

void shadow_rows(const Shadow& s, double cv0, double step, int n, double* lo, double* hi) {
  shadow_batch(s, cv0, step, n, lo, hi);
}

}  // namespace tf
