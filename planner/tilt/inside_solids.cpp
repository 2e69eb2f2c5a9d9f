#include "inside_solids.hpp"

#include <tbb/parallel_for.h>

#include <array>
#include <cmath>

#include "tiltfield/core/triangle_bvh.hpp"

namespace tf {
namespace {

using Eigen::Vector3d;

// Does the ray o + t d (t > 0) cross triangle tr? (Moller-Trumbore; a ray in the triangle's plane does not.)
bool crosses(const Vector3d& o, const Vector3d& d, const Triangle& tr) {
  const Vector3d e1 = tr.b - tr.a, e2 = tr.c - tr.a;
  const Vector3d p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-300) return false;
  const Vector3d s = o - tr.a;
  const double u = s.dot(p) / det;
  if (u < 0.0 || u > 1.0) return false;
  const Vector3d q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (v < 0.0 || u + v > 1.0) return false;
  return e2.dot(q) / det > 0.0;
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

// Odd number of crossings of the ray from o along d.
bool odd_crossings(const TriangleBvh& bvh, const Vector3d& o, const Vector3d& d) {
  const Vector3d inv = d.cwiseInverse();
  bool odd = false;
  // The hierarchy's best-first walk as a plain traversal: boxes the ray meets bound 0 (visited), others 2,
  // and no leaf ever improves on 1.
  bvh.minimum([&](const Vector3d& lo, const Vector3d& hi) { return meets_box(o, inv, lo, hi) ? 0.0 : 2.0; },
              [&](int i, double) {
                odd ^= crosses(o, d, bvh.triangle(i));
                return 1.0;
              },
              1.0);
  return odd;
}

bool inside(const TriangleBvh& bvh, const Vector3d& p) {
  // Directions with no simple ratio between their components: a mesh's edges and faces are seldom
  // parallel to them.
  static const std::array<Vector3d, 3> dirs = {Vector3d(0.5377, 0.4214, 0.7303).normalized(),
                                               Vector3d(-0.6311, 0.3877, -0.6718).normalized(),
                                               Vector3d(0.2617, -0.8934, 0.3652).normalized()};
  int votes = 0;
  for (const Vector3d& d : dirs) votes += odd_crossings(bvh, p, d) ? 1 : 0;
  return votes >= 2;
}

}  // namespace

std::vector<int8_t> points_inside_solids(const std::vector<std::vector<const Mesh*>>& sets,
                                         const std::vector<Eigen::Vector3d>& points) {
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
