// The grinder's axes -> the wheel's pose in the blank frame; wheel profiles; move increments.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "tiltfield/grind/grind.hpp"

namespace tf::grind {
namespace {
constexpr double kDeg = M_PI / 180.0;
}

std::vector<Eigen::Vector2d> make_wheel_profile(double radius, double thickness, double edge_radius,
                                                double chord_tolerance, double max_step) {
  const double h = 0.5 * thickness, e = std::min(edge_radius, std::min(h, radius));
  std::vector<Eigen::Vector2d> left;  // corner at t = -h, from the face (phi = 0) to the rim (phi = 90 deg)
  if (e > 0.0) {
    const double dphi = 2.0 * std::acos(std::max(-1.0, 1.0 - chord_tolerance / e));
    const int n = std::max(2, static_cast<int>(std::ceil(0.5 * M_PI / std::max(dphi, 1e-6))));
    for (int i = 0; i <= n; ++i) {
      const double phi = 0.5 * M_PI * i / n;
      left.emplace_back(-h + e - e * std::cos(phi), radius - e + e * std::sin(phi));
    }
  } else {
    left.emplace_back(-h, radius);
  }
  std::vector<Eigen::Vector2d> out = left;
  // Flat rim: rings close enough that an oblique plane's ellipse arc between them stays near its chord.
  const double t0 = -h + e, t1 = h - e;
  const int m = std::max(1, static_cast<int>(std::ceil((t1 - t0) / max_step)));
  for (int i = 1; i < m; ++i) out.emplace_back(t0 + (t1 - t0) * i / m, radius);
  for (auto it = left.rbegin(); it != left.rend(); ++it) {
    const Eigen::Vector2d q(-it->x(), it->y());
    if (q.x() > out.back().x() + 1e-12) out.push_back(q);
  }
  return out;
}

WheelPose wheel_pose(const Axes& ax) {
  const Eigen::Matrix3d Rw = Eigen::AngleAxisd(-ax.w * kDeg, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Matrix3d Ra = Eigen::AngleAxisd(-ax.a * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  WheelPose p;
  p.centre = Ra * (Rw * Eigen::Vector3d(ax.x, ax.y, ax.z) - ax.u * Eigen::Vector3d::UnitZ());
  p.axis = Ra * Rw * Eigen::Vector3d::UnitX();
  return p;
}

Axes interpolate(const Axes& f, const Axes& t, double s) {
  auto lerp = [s](double a, double b) { return a + (b - a) * s; };
  return {lerp(f.x, t.x), lerp(f.y, t.y), lerp(f.z, t.z), lerp(f.u, t.u), lerp(f.a, t.a), lerp(f.w, t.w)};
}

int increments(const Axes& f, const Axes& t, const Blank& blank, double step) {
  // First-order bound of the relative displacement of any blank point: wheel translation + blank slide +
  // blank rotation at radius r + swivel about the W pivot at the blank's farthest distance from it.
  const double swivel_arm = std::hypot(blank.radius, blank.length + std::max(std::abs(f.u), std::abs(t.u)));
  const double d = std::sqrt((t.x - f.x) * (t.x - f.x) + (t.y - f.y) * (t.y - f.y) + (t.z - f.z) * (t.z - f.z)) +
                   std::abs(t.u - f.u) + std::abs(t.a - f.a) * kDeg * blank.radius +
                   std::abs(t.w - f.w) * kDeg * swivel_arm;
  const double n = std::ceil(d / std::max(step, 1e-6));
  return static_cast<int>(std::clamp(n, 1.0, kMaxIncrements + 1.0));
}

}  // namespace tf::grind
