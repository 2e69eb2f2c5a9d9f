#include "inside_solids.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

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
  if (std::abs(det) < 1e-300) return 0;
  const Vector3d s = o - tr.a;
  const double u = s.dot(p) / det;
  if (u < 0.0 || u > 1.0) return 0;
  const Vector3d q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (v < 0.0 || u + v > 1.0) return 0;
  if (!(e2.dot(q) / det > 0.0)) return 0;
  return det < 0.0 ? 1 : -1;  // det = -d . (e1 x e2): negative when d runs along the normal
}

// Does the ray o + t d (t >= 0) meet the box [lo, hi]? (Slabs; inv = 1 / d componentwise.)
bool meets_box(const Vector3d& o, const Vector3d& inv, const Vector3d& lo, const Vector3d& hi) {
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    double a = (lo[k] - o[k]) * inv[k], b = (hi[k] - o[k]) * inv[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return false;
  }
  return true;
}

// The winding number of the surface about o, counted along the ray from o along d: how many times more
// it leaves solids than it enters them. Not parity: two closed bodies overlapping in one mesh (an
// assembled fixture) wind twice where they overlap.
int winding(const TriangleBvh& bvh, const Vector3d& o, const Vector3d& d) {
  const Vector3d inv = d.cwiseInverse();
  int w = 0;
  // The hierarchy's best-first walk as a plain traversal: boxes the ray meets bound 0 (visited), others 2,
  // and no leaf ever improves on 1.
  bvh.minimum([&](const Vector3d& lo, const Vector3d& hi) { return meets_box(o, inv, lo, hi) ? 0.0 : 2.0; },
              [&](int i, double) {
                w += crossing(o, d, bvh.triangle(i));
                return 1.0;
              },
              1.0);
  return w;
}

bool inside(const TriangleBvh& bvh, const Vector3d& p) {
  // Directions with no simple ratio between their components: a mesh's edges and faces are seldom
  // parallel to them.
  static const std::array<Vector3d, 3> dirs = {Vector3d(0.5377, 0.4214, 0.7303).normalized(),
                                               Vector3d(-0.6311, 0.3877, -0.6718).normalized(),
                                               Vector3d(0.2617, -0.8934, 0.3652).normalized()};
  int votes = 0;
  for (const Vector3d& d : dirs) votes += winding(bvh, p, d) > 0 ? 1 : 0;
  return votes >= 2;
}

}  // namespace

std::vector<int8_t> points_inside_solids(const std::vector<std::vector<const Mesh*>>& sets,
                                         const std::vector<Eigen::Vector3d>& points) {
  if (sets.size() > 127) throw std::invalid_argument("points_inside_solids: more than 127 obstacle sets");
  std::vector<int8_t> out(points.size(), -1);
  for (size_t s = sets.size(); s-- > 0;) {  // backwards: the first set containing a point is the one kept
    for (const Mesh* m : sets[s]) {
      if (m->n_faces() == 0 || !is_closed(*m) || !(signed_volume(*m) > 0.0)) continue;
      const TriangleBvh bvh({m});
      const Eigen::AlignedBox3d box = bvh.bounds();
      tbb::parallel_for(size_t{0}, points.size(), [&](size_t i) {
        if (box.contains(points[i]) && inside(bvh, points[i])) out[i] = static_cast<int8_t>(s);
      });
    }
  }
  return out;
}

}  // namespace tf
