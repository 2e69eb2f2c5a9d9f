#include "scene_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace tf::scenes {

namespace {
// Deviation of the chord a-b from the curve points at parameter fractions 1/4, 1/2, 3/4 (the midpoint
// alone misses S-shaped pieces).
double chord_deviation(const std::function<std::vector<Eigen::Vector3d>(double)>& eval, double ta, double tb,
                       const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  double worst = 0.0;
  for (double f : {0.25, 0.5, 0.75}) {
    const std::vector<Eigen::Vector3d> m = eval(ta + f * (tb - ta));
    for (size_t k = 0; k < m.size(); ++k) {
      const Eigen::Vector3d d = b[k] - a[k];
      const double len2 = d.squaredNorm();
      const double u = len2 > 0 ? std::clamp((m[k] - a[k]).dot(d) / len2, 0.0, 1.0) : 0.0;
      worst = std::max(worst, (m[k] - (a[k] + u * d)).norm());
    }
  }
  return worst;
}
}  // namespace

std::vector<double> sample_by_chord(const std::function<std::vector<Eigen::Vector3d>(double)>& eval, double t0,
                                    double t1, double tolerance, int min_intervals) {
  if (!(t1 > t0) || !(tolerance > 0) || min_intervals < 1)
    throw std::invalid_argument("sample_by_chord: need t1 > t0, tolerance > 0, min_intervals >= 1");
  std::vector<double> out;
  out.push_back(t0);
  // Depth-first bisection keeps the output sorted without a final sort.
  struct Piece {
    double ta, tb;
    std::vector<Eigen::Vector3d> a, b;
    int depth;
  };
  for (int i = 0; i < min_intervals; ++i) {
    const double ta = t0 + (t1 - t0) * i / min_intervals;
    const double tb = i + 1 == min_intervals ? t1 : t0 + (t1 - t0) * (i + 1) / min_intervals;
    std::vector<Piece> stack;
    stack.push_back({ta, tb, eval(ta), eval(tb), 0});
    while (!stack.empty()) {
      Piece p = std::move(stack.back());
      stack.pop_back();
      if (p.depth < 20 && chord_deviation(eval, p.ta, p.tb, p.a, p.b) > tolerance) {
        const double tm = 0.5 * (p.ta + p.tb);
        std::vector<Eigen::Vector3d> m = eval(tm);
        // Right half pushed first so the left half is processed (and emitted) first.
        stack.push_back({tm, p.tb, m, std::move(p.b), p.depth + 1});
        stack.push_back({p.ta, tm, std::move(p.a), std::move(m), p.depth + 1});
      } else {
        out.push_back(p.tb);
      }
    }
  }
  return out;
}

int circle_segments(double radius, double tolerance) {
  if (!(radius > 0) || !(tolerance > 0)) return 12;
  const double half = std::acos(std::max(-1.0, 1.0 - std::min(tolerance / radius, 2.0)));
  return std::max(12, static_cast<int>(std::ceil(std::numbers::pi / half)));
}

Mesh revolve_profile(const std::vector<Eigen::Vector2d>& profile, int segments) {
  if (profile.size() < 3 || profile.front().x() != 0.0 || profile.back().x() != 0.0 || segments < 3)
    throw std::invalid_argument("revolve_profile: the profile must start and end on the axis");
  const int n = segments;
  std::vector<int> first(profile.size());  // index of the first vertex of each profile point
  std::vector<Eigen::Vector3d> verts;
  for (size_t i = 0; i < profile.size(); ++i) {
    first[i] = static_cast<int>(verts.size());
    const double r = profile[i].x(), z = profile[i].y();
    const bool pole = i == 0 || i + 1 == profile.size();
    if (pole) {
      verts.emplace_back(0.0, 0.0, z);
    } else {
      if (!(r > 0)) throw std::invalid_argument("revolve_profile: an inner profile point lies on the axis");
      for (int j = 0; j < n; ++j) {
        const double t = 2.0 * std::numbers::pi * j / n;
        verts.emplace_back(r * std::cos(t), r * std::sin(t), z);
      }
    }
  }
  std::vector<Eigen::Vector3i> faces;
  for (size_t i = 0; i + 1 < profile.size(); ++i) {
    const bool pa = i == 0, pb = i + 2 == profile.size();
    for (int j = 0; j < n; ++j) {
      const int j1 = (j + 1) % n;
      // Ring i at angles j, j+1 (a, b) and ring i+1 (d, c): the profile runs counter-clockwise with the
      // solid on its left, so (theta direction) x (profile direction) points outward.
      const int a = pa ? first[i] : first[i] + j, b = pa ? first[i] : first[i] + j1;
      const int d = pb ? first[i + 1] : first[i + 1] + j, c = pb ? first[i + 1] : first[i + 1] + j1;
      if (!pa) faces.emplace_back(a, b, c);
      if (!pb) faces.emplace_back(a, c, d);
    }
  }
  Eigen::MatrixX3d V(verts.size(), 3);
  for (size_t i = 0; i < verts.size(); ++i) V.row(static_cast<Eigen::Index>(i)) = verts[i].transpose();
  Eigen::MatrixX3i F(faces.size(), 3);
  for (size_t i = 0; i < faces.size(); ++i) F.row(static_cast<Eigen::Index>(i)) = faces[i].transpose();
  return mesh_from_arrays(V, F);
}

Mesh extrude_along_x(const std::vector<Eigen::Vector2d>& section, double x0, double x1) {
  const int n = static_cast<int>(section.size());
  if (n < 3 || !(x1 > x0)) throw std::invalid_argument("extrude_along_x: need a polygon and x1 > x0");
  Eigen::MatrixX3d V(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    V.row(i) << x0, section[i].x(), section[i].y();
    V.row(n + i) << x1, section[i].x(), section[i].y();
  }
  std::vector<Eigen::Vector3i> faces;
  // End caps: the section is counter-clockwise seen from +x, so the x1 cap keeps its order and the x0 cap
  // is reversed (fans, valid for a convex section).
  for (int i = 1; i + 1 < n; ++i) {
    faces.emplace_back(n, n + i, n + i + 1);
    faces.emplace_back(0, i + 1, i);
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    faces.emplace_back(i, j, n + j);
    faces.emplace_back(i, n + j, n + i);
  }
  Eigen::MatrixX3i F(faces.size(), 3);
  for (size_t i = 0; i < faces.size(); ++i) F.row(static_cast<Eigen::Index>(i)) = faces[i].transpose();
  return mesh_from_arrays(V, F);
}

Mesh box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  // A box is the rectangle (y, z) extruded along x.
  return extrude_along_x({{lo.y(), lo.z()}, {hi.y(), lo.z()}, {hi.y(), hi.z()}, {lo.y(), hi.z()}}, lo.x(), hi.x());
}

std::vector<Eigen::Vector3d> resample_polyline(const std::vector<Eigen::Vector3d>& knots, double step) {
  if (!(step > 0)) throw std::invalid_argument("resample_polyline: step must be positive");
  std::vector<Eigen::Vector3d> out;
  if (knots.empty()) return out;
  out.push_back(knots.front());
  for (size_t i = 1; i < knots.size(); ++i) {
    const Eigen::Vector3d a = knots[i - 1], b = knots[i];
    const double len = (b - a).norm();
    if (len <= 0) continue;
    const int n = std::max(1, static_cast<int>(std::ceil(len / step - 1e-9)));
    for (int k = 1; k <= n; ++k) out.push_back(a + (b - a) * (static_cast<double>(k) / n));
  }
  return out;
}

}  // namespace tf::scenes
