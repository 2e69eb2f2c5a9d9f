// The swept sphere (a capsule) against a row of parallel lattice rays, in one batch.
//
// This is the verifier's innermost loop: a ball end moving 0.1 mm at 0.05 mm resolution meets some
// 20 000 rays a block, nearly all of them a few ulps from the material they touch. The loop below is
// branch-free per ray so that the compiler vectorises it; it is built for AVX-512, AVX2 and baseline
// x86-64 (picked at load time) with floating-point contraction off, so every build gives the same bits.
//
// Geometry: the capsule is {p0 + s d + x : s in [0, 1], |x| <= r}, convex, so a ray meets it in one
// interval: the hull of its meetings with the start sphere, the end sphere and the swept disc region
// (the cylinder of radius r about the segment, between the planes through p0 and p0 + d normal to d).
// Each ray's origin is put in the plane through p0 normal to the ray, which keeps the quadratics'
// coefficients of the order of r (no cancellation against the lattice's coordinates).
#include <cmath>
#include <limits>

#include "row_kernels.hpp"
#include "sweep_rows.hpp"

namespace tf {
namespace {

using row_kernels::kInf;

struct RowConstants {
  double r2, wv, w1v, du, dv, dd;      // r^2; v offsets of the ray row from the start / end centre; d
  double de, A, inv_a, inv_c, inv_len, len;
};

// kMoving: d != 0. kAcross: the ray is not parallel to d. kSlanted: d has a component along the ray.
template <bool kMoving, bool kAcross, bool kSlanted>
[[gnu::always_inline]] inline void capsule_lane(const RowConstants& k, double wu, double shift, double& t0, double& t1) {
  const double q = wu * wu + k.wv * k.wv;
  const double disc0 = k.r2 - q;
  const double s0 = std::sqrt(disc0 > 0.0 ? disc0 : 0.0);
  double lo = disc0 > 0.0 ? -s0 : kInf;
  double hi = disc0 > 0.0 ? s0 : -kInf;
  if constexpr (kMoving) {
    const double w1u = wu - k.du;
    const double disc1 = k.r2 - (w1u * w1u + k.w1v * k.w1v);
    const double s1 = std::sqrt(disc1 > 0.0 ? disc1 : 0.0);
    const double a1 = k.dd - s1, b1 = k.dd + s1;
    // Selects and min/max only, no branches: the loop vectorises.
    const double a1m = disc1 > 0.0 ? a1 : kInf, b1m = disc1 > 0.0 ? b1 : -kInf;
    lo = a1m < lo ? a1m : lo;
    hi = b1m > hi ? b1m : hi;
    if constexpr (kAcross) {
      // Distance along d of the ray's origin, and the quadratic of the ray in the infinite cylinder.
      const double dw = (k.du * wu + k.dv * k.wv) * k.inv_len;
      const double B = -k.de * dw, C = q - dw * dw - k.r2;
      const double disc = B * B - k.A * C;
      const double sq = std::sqrt(disc > 0.0 ? disc : 0.0);
      double a = (-B - sq) * k.inv_a, b = (-B + sq) * k.inv_a;
      if constexpr (kSlanted) {
        // Between the two end planes: s = (dw + t de) / len in [0, 1].
        const double sa = -dw * k.inv_c, sb = (k.len - dw) * k.inv_c;
        const double smin = sa < sb ? sa : sb, smax = sa < sb ? sb : sa;
        a = a > smin ? a : smin;
        b = b < smax ? b : smax;
        b = disc > 0.0 ? b : -kInf;
      } else {
        // d is across the ray: the whole ray is between the end planes, or none of it.
        b = dw < 0.0 ? -kInf : b;
        b = dw > k.len ? -kInf : b;
        b = disc > 0.0 ? b : -kInf;
      }
      // A miss (b <= a) leaves lo and hi alone.
      const double am = b > a ? a : kInf, bm = b > a ? b : -kInf;
      lo = am < lo ? am : lo;
      hi = bm > hi ? bm : hi;
    }
  }
  const bool hit = hi > lo;
  t0 = hit ? lo + shift : kInf;
  t1 = hit ? hi + shift : -kInf;
}

template <bool kMoving, bool kAcross, bool kSlanted>
[[gnu::always_inline]] inline void capsule_row(const RowConstants& k, double wu0, double step, int n, double shift,
                                               double* __restrict t0, double* __restrict t1) {
  row_kernels::in_blocks(n, t0, t1, [&](int i, double& a, double& b) __attribute__((always_inline)) {
    capsule_lane<kMoving, kAcross, kSlanted>(k, wu0 + step * i, shift, a, b);
  });
}

TF_VECTOR_CLONES
void capsule_rows(const SweptPart& p, const Eigen::Vector3d& o, int dir, int u, double step, int n, double* t0, double* t1) {
  const int v = 3 - dir - u;
  RowConstants k;
  k.r2 = p.radius * p.radius;
  k.wv = o[v] - p.p0[v];
  k.w1v = k.wv - p.d[v];
  k.du = p.d[u];
  k.dv = p.d[v];
  k.dd = p.d[dir];
  k.de = p.dir_cos[dir];
  k.A = 1.0 - k.de * k.de;
  k.inv_a = p.inv_sin2[dir];
  k.inv_c = p.inv_cos[dir];
  k.inv_len = p.inv_len;
  k.len = p.len;
  const double wu0 = o[u] - p.p0[u];
  // t is measured from o; the kernel measures it from the plane through p0.
  const double shift = p.p0[dir] - o[dir];
  if (!(p.len > 0.0)) capsule_row<false, false, false>(k, wu0, step, n, shift, t0, t1);
  else if (!(k.inv_a > 0.0)) capsule_row<true, false, false>(k, wu0, step, n, shift, t0, t1);
  else if (k.inv_c != 0.0) capsule_row<true, true, true>(k, wu0, step, n, shift, t0, t1);
  else capsule_row<true, true, false>(k, wu0, step, n, shift, t0, t1);
}

}  // namespace

void capsule_intervals(const SweptPart& part, const Eigen::Vector3d& o, int dir, int u, double step, int n,
                       double* t0, double* t1) {
  capsule_rows(part, o, dir, u, step, n, t0, t1);
}

}  // namespace tf
