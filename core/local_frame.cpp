#include "tiltfield/core/local_frame.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "tiltfield/core/angles.hpp"

namespace tf {

std::vector<LocalFrame> local_frames(const ToolPath& path) {
  const size_t n = path.rows.size();
  std::vector<LocalFrame> frames(n);
  Eigen::Vector3d prev_f = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& nrm = path.rows[i].n;
    // Neighbours at the row's own point (a repeated row) are passed over: the first row of a path that
    // repeats it had taken an arbitrary feed direction, its sideways axis read as lead, and the two rows of
    // a repeated corner had taken the directions before and after it (black-box testing). A reversal on a
    // repeated point, whose distinct neighbours coincide, keeps the neighbours it has: it turns between
    // its rows.
    const auto& p = path.rows;
    const size_t a0 = i == 0 ? 0 : i - 1, b0 = i + 1 < n ? i + 1 : i;
    size_t a = a0, b = b0;
    while (a > 0 && p[a].p == p[i].p) --a;
    while (b + 1 < n && p[b].p == p[i].p) ++b;
    Eigen::Vector3d d = p[b].p - p[a].p;
    if ((d - d.dot(nrm) * nrm).norm() <= 1e-9) d = p[b0].p - p[a0].p;
    d -= d.dot(nrm) * nrm;
    Eigen::Vector3d f;
    if (d.norm() > 1e-9) {
      f = d.normalized();
    } else if (prev_f.squaredNorm() > 0.5) {
      f = prev_f - prev_f.dot(nrm) * nrm;
      f = f.norm() > 1e-9 ? f.normalized() : nrm.unitOrthogonal();
    } else {
      f = nrm.unitOrthogonal();
    }
    frames[i] = {f, nrm, f.cross(nrm)};
    prev_f = f;
  }
  return frames;
}

Eigen::Vector3d axis_from_lead_tilt(const LocalFrame& fr, double lead_deg, double tilt_deg) {
  const double l = lead_deg * kDeg, t = tilt_deg * kDeg;
  return (std::cos(l) * (std::cos(t) * fr.n + std::sin(t) * fr.t) + std::sin(l) * fr.f).normalized();
}

Eigen::Vector2d lead_tilt_from_axis(const LocalFrame& fr, const Eigen::Vector3d& axis) {
  const double s = std::clamp(axis.dot(fr.f), -1.0, 1.0);
  return {std::asin(s) / kDeg, std::atan2(axis.dot(fr.t), axis.dot(fr.n)) / kDeg};
}

Eigen::Vector3d slerp_axis(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double s) {
  const double w = angle_between(a, b);
  if (w < 1e-9) return (a + (b - a) * s).normalized();
  const double sw = std::sin(w);
  return (std::sin((1.0 - s) * w) / sw * a + std::sin(s * w) / sw * b).normalized();
}

}  // namespace tf
