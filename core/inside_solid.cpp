// Point containment in a closed mesh by the winding number along rays.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "tiltfield/core/triangle_bvh.hpp"

namespace tf {
namespace {

using Eigen::Vector3d;

// The ray o + t d (t > 0) crossing triangle tr: +1 leaving through its front (the side its normal faces),
// -1 entering, 0 missing it (Moller-Trumbore; a ray in the triangle's plane misses).
int crossing(const Vector3d& o, const Vector3d& d, const Triangle& tr) {
  const Vector3d e1 = tr.b - tr.a, e2 = tr.c - tr.a;
  const Vector3d p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-14 * (e1.squaredNorm() + e2.squaredNorm())) return 0;  // parallel or degenerate
  const Vector3d s = o - tr.a;
  const double u = s.dot(p) / det;
  if (u < 0.0 || u > 1.0) return 0;
  const Vector3d q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (v < 0.0 || u + v > 1.0) return 0;
  if (!(e2.dot(q) / det > 0.0)) return 0;
  return det < 0.0 ? 1 : -1;  // det = -d . (e1 x e2): negative when d runs along the normal
}

// The winding number of the surface about o, counted along the ray from o along d: how many times more
// it leaves solids than it enters them (two closed bodies overlapping in one mesh wind twice there).
int winding(const TriangleBvh& bvh, const Vector3d& o, const Vector3d& d) {
  const Vector3d inv = d.cwiseInverse();
  int w = 0;
  // The best-first walk as a plain traversal: boxes the ray meets bound 0 (visited), the others infinity,
  // and no leaf ever lowers the minimum below the start (1).
  bvh.minimum(
      [&](const Vector3d& lo, const Vector3d& hi) {
        const Vector3d t0 = (lo - o).cwiseProduct(inv), t1 = (hi - o).cwiseProduct(inv);
        const double enter = std::max(t0.cwiseMin(t1).maxCoeff(), 0.0), leave = t0.cwiseMax(t1).minCoeff();
        return leave >= enter ? 0.0 : std::numeric_limits<double>::infinity();
      },
      [&](int i, double) {
        w += crossing(o, d, bvh.triangle(i));
        return 1.0;
      },
      1.0);
  return w;
}

}  // namespace

bool inside_solid(const TriangleBvh& bvh, const Eigen::Vector3d& p) {
  if (bvh.empty() || !bvh.bounds().contains(p)) return false;
  // Fixed directions with no zero component (the slab test needs no special case) and no simple relation
  // to the axes or to each other: a ray grazing an edge or a vertex of one is unlikely to graze one with
  // another, and the majority decides.
  static const std::array<Vector3d, 3> dirs = {Vector3d(0.2345, 0.4567, 0.8581).normalized(),
                                               Vector3d(-0.6789, 0.1234, 0.7239).normalized(),
                                               Vector3d(0.3141, -0.8272, -0.4657).normalized()};
  int votes = 0;
  for (const Vector3d& d : dirs) votes += winding(bvh, p, d) > 0 ? 1 : 0;
  return votes >= 2;
}

}  // namespace tf
