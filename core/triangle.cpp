// Exact point, segment and triangle distances (Ericson, Real-Time Collision Detection, 5.1).
#include <algorithm>
#include <cmath>

#include "tiltfield/core/triangle.hpp"

namespace tf {
using Eigen::Vector3d;

Vector3d closest_point_on_triangle(const Vector3d& p, const Triangle& t) {
  const Vector3d ab = t.b - t.a, ac = t.c - t.a, ap = p - t.a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return t.a;
  const Vector3d bp = p - t.b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return t.b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return t.a + v * ab;
  }
  const Vector3d cp = p - t.c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return t.c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return t.a + w * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return t.b + w * (t.c - t.b);
  }
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) {  // degenerate triangle: nearest of its edges
    Vector3d best = t.a;
    for (const auto& [u, w] : {std::pair{t.a, t.b}, std::pair{t.b, t.c}, std::pair{t.c, t.a}}) {
      const Vector3d e = w - u;
      const double l2 = e.squaredNorm();
      const double s = l2 > 0 ? std::clamp((p - u).dot(e) / l2, 0.0, 1.0) : 0.0;
      const Vector3d q = u + s * e;
      if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
    }
    return best;
  }
  const double v = vb / denom, w = vc / denom;
  return t.a + ab * v + ac * w;
}

double segment_segment_distance(const Vector3d& p1, const Vector3d& q1, const Vector3d& p2, const Vector3d& q2,
                                double* s_out) {
  // Ericson 5.1.9, clamped parameters.
  const Vector3d d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  constexpr double eps = 1e-18;
  if (s_out) *s_out = 0;
  if (a <= eps && e <= eps) return r.norm();
  if (a <= eps) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= eps) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > eps * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  if (s_out) *s_out = s;
  return ((p1 + d1 * s) - (p2 + d2 * t)).norm();
}

double segment_triangle_distance(const Vector3d& p0, const Vector3d& p1, const Triangle& t, double* s_out) {
  // Crossing: the segment's endpoints on opposite sides of the plane and the crossing point inside.
  const Vector3d n = (t.b - t.a).cross(t.c - t.a);
  const double s0 = n.dot(p0 - t.a), s1 = n.dot(p1 - t.a);
  if ((s0 <= 0 && s1 >= 0) || (s0 >= 0 && s1 <= 0)) {
    if (s0 != s1) {
      const Vector3d x = p0 + (p1 - p0) * (s0 / (s0 - s1));
      const double u = n.dot((t.b - t.a).cross(x - t.a)), v = n.dot((t.c - t.b).cross(x - t.b)),
                   w = n.dot((t.a - t.c).cross(x - t.c));
      if ((u >= 0 && v >= 0 && w >= 0) || (u <= 0 && v <= 0 && w <= 0)) {
        if (s_out) *s_out = s0 / (s0 - s1);
        return 0.0;
      }
    }
  }
  const double d0 = (closest_point_on_triangle(p0, t) - p0).norm(), d1 = (closest_point_on_triangle(p1, t) - p1).norm();
  double d = d0 <= d1 ? d0 : d1, s = d0 <= d1 ? 0.0 : 1.0;
  const Vector3d* e[3][2] = {{&t.a, &t.b}, {&t.b, &t.c}, {&t.c, &t.a}};
  for (const auto& edge : e) {
    double se = 0;
    const double de = segment_segment_distance(p0, p1, *edge[0], *edge[1], &se);
    if (de < d) d = de, s = se;
  }
  if (s_out) *s_out = s;
  return d;
}

std::vector<Triangle> mesh_triangles(const std::vector<const Mesh*>& meshes) {
  std::vector<Triangle> tris;
  size_t n = 0;
  for (const Mesh* m : meshes) n += m->n_faces();
  tris.reserve(n);
  for (const Mesh* m : meshes) {
    for (auto f : m->faces()) {
      Vector3d v[3];
      int k = 0;
      for (auto vh : m->fv_range(f)) {
        if (k < 3) v[k] = to_eigen(m->point(vh));
        ++k;
      }
      if (k == 3) tris.push_back({v[0], v[1], v[2]});
    }
  }
  return tris;
}

}  // namespace tf
