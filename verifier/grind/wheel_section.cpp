#include "wheel_section.hpp"

#include <algorithm>
#include <cmath>

namespace tf::grind::detail {

PoseInfo pose_info(const WheelPose& pose, const Wheel& wheel, const Blank& blank, double a_deg) {
  PoseInfo info;
  info.pose = pose;
  const Eigen::Vector3d& a = pose.axis;
  // The generators' angles start from a x z, which turns with the blank (A) and follows the swivel (W), so
  // that a generator keeps its id from one pose to the next (turning_sweep follows points by id). For a
  // spindle along the blank's axis (W = +-90) a x z vanishes: the blank's own x, turned by A, instead (a
  // fixed x had left the ids in place while the blank turned, and the sweep fell back to the hull of both
  // sections, cutting 0.008 mm too deep at the default step; black-box testing).
  const double turn = -a_deg * M_PI / 180.0;
  const Eigen::Vector3d helper =
      std::abs(a.z()) < 0.999 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d(std::cos(turn), std::sin(turn), 0.0);
  info.u1 = a.cross(helper).normalized();
  info.u2 = a.cross(info.u1);
  const double h = 0.5 * wheel.thickness;
  const double az = std::min(1.0, std::abs(a.z()));
  const double ext = wheel.radius * std::sqrt(std::max(0.0, 1.0 - az * az)) + h * az;
  info.z_lo = pose.centre.z() - ext;
  info.z_hi = pose.centre.z() + ext;
  const double reach = std::hypot(wheel.radius, h);
  info.far = std::hypot(pose.centre.x(), pose.centre.y()) - reach > blank.radius ||
             info.z_hi < 0.0 || info.z_lo > blank.length;
  return info;
}

void wheel_section_points(const PoseInfo& info, const std::vector<Eigen::Vector2d>& profile, double z0,
                          const std::vector<Eigen::Vector2d>& trig, std::vector<Eigen::Vector2d>& out,
                          std::vector<int>* ids) {
  const int rings = static_cast<int>(profile.size());
  const Eigen::Vector3d& c = info.pose.centre;
  const Eigen::Vector3d& a = info.pose.axis;
  // Ring chords: each ring's disc {|p - o| <= rho, a.(p - o) = 0} meets the plane z = z0 in a segment.
  const double dxy2 = a.x() * a.x() + a.y() * a.y();
  if (dxy2 > 1e-18) {
    const Eigen::Vector2d dir = Eigen::Vector2d(a.y(), -a.x()) / std::sqrt(dxy2);
    // The disc at offset t of radius rho: its chord's ends, or its one point where the plane touches it.
    auto chord = [&](double t, double rho, int id, bool touching) {
      const Eigen::Vector3d o = c + t * a;
      const double k = a.dot(o) - a.z() * z0;
      const Eigen::Vector2d p0 = k / dxy2 * Eigen::Vector2d(a.x(), a.y());
      const Eigen::Vector3d w(p0.x() - o.x(), p0.y() - o.y(), z0 - o.z());
      const double b = dir.x() * w.x() + dir.y() * w.y();
      if (touching) {
        out.push_back(p0 - b * dir);
        if (ids) ids->push_back(id);
        return;
      }
      const double disc = b * b - (w.squaredNorm() - rho * rho);
      if (disc < 0.0) return;
      const double s = std::sqrt(disc);
      out.push_back(p0 + (-b - s) * dir);
      out.push_back(p0 + (-b + s) * dir);
      if (ids) ids->insert(ids->end(), {id, id + 1});
    };
    for (int r = 0; r < rings; ++r) chord(profile[size_t(r)].x(), profile[size_t(r)].y(), 2 * r, false);
    // Between two rings the wheel is a cone's frustum, and the plane's distance from the axis in a disc's
    // plane, m(t) = |z0 - c.z - t a.z| / sqrt(dxy2), is linear in t: where it equals rho(t) the plane touches
    // the frustum, the section's extreme point along the spindle. Without it the section ended at the
    // last ring that reaches the plane: a ground slot came out narrower by up to a ring spacing, and a
    // wheel given by a coarse profile (a V of three points) ground nothing where only its rim reached
    // (black-box testing).
    const double inv = 1.0 / std::sqrt(dxy2);
    const double m0 = (z0 - c.z()) * inv, mt = -a.z() * inv;  // m(t) = |m0 + mt t|
    const int vertex_ids = 2 * rings + rings * static_cast<int>(trig.size());
    for (int r = 0; r + 1 < rings; ++r) {
      const double t0 = profile[size_t(r)].x(), r0 = profile[size_t(r)].y();
      const double t1 = profile[size_t(r + 1)].x(), r1 = profile[size_t(r + 1)].y();
      const double slope = (r1 - r0) / (t1 - t0);
      for (int side = 0; side < 2; ++side) {
        const double sg = side == 0 ? 1.0 : -1.0;  // rho(t) = sg * (m0 + mt t)
        const double den = slope - sg * mt;
        if (std::abs(den) < 1e-15) continue;
        const double t = (sg * m0 - r0 + slope * t0) / den;
        if (!(t > t0 && t < t1)) continue;
        chord(t, r0 + slope * (t - t0), vertex_ids + 2 * r + side, true);
      }
    }
  }
  // Generators: only needed when rings are nearly parallel to the plane (their chords get sparse).
  if (std::abs(a.z()) <= 0.5 || trig.size() < 3) return;
  const double perp = std::sqrt(std::max(0.0, 1.0 - a.z() * a.z()));
  const double base = c.z() - z0;
  // A generator's end within kOnPlane of the plane lies on it: a face of the wheel exactly in the plane
  // (a swivel of 90 deg leaves cos 90 deg = 6e-17 in the axis) had the sign of that rounding decide, so
  // the generators on one side only met the plane and half the face was ground (found by black-box testing).
  constexpr double kOnPlane = 1e-9;  // mm
  auto on = [](double v) { return std::abs(v) <= kOnPlane ? 0.0 : v; };
  const size_t last = profile.size() - 1;
  for (size_t i = 0; i < last; ++i) {
    const double t0 = profile[i].x(), r0 = profile[i].y(), t1 = profile[i + 1].x(), r1 = profile[i + 1].y();
    const double m0 = base + t0 * a.z(), m1 = base + t1 * a.z();
    if ((m0 - r0 * perp > kOnPlane && m1 - r1 * perp > kOnPlane) || (m0 + r0 * perp < -kOnPlane && m1 + r1 * perp < -kOnPlane))
      continue;
    for (size_t g = 0; g < trig.size(); ++g) {
      const Eigen::Vector2d& cs = trig[g];
      const Eigen::Vector3d dir = cs.x() * info.u1 + cs.y() * info.u2;
      const double s0 = on(m0 + r0 * dir.z()), s1 = on(m1 + r1 * dir.z());
      if ((s0 > 0 && s1 > 0) || (s0 < 0 && s1 < 0)) continue;
      auto add = [&](double f, size_t id) {
        const Eigen::Vector3d p = c + (t0 + f * (t1 - t0)) * a + (r0 + f * (r1 - r0)) * dir;
        out.emplace_back(p.x(), p.y());
        if (ids) ids->push_back(2 * rings + static_cast<int>(id * trig.size() + g));
      };
      // Both ends on the plane: the generator lies in it. Its start is added here, its end by the next
      // generator's start (or, for the profile's last, under the unused index `last`).
      if (s0 == 0.0 && s1 == 0.0) {
        add(0.0, i);
        if (i + 1 == last) add(1.0, last);
        continue;
      }
      add(s0 == s1 ? 0.0 : s0 / (s0 - s1), i);
    }
  }
}

constexpr double kRimRingStep = 0.25;  // mm, as make_wheel_profile's default max_step

std::vector<Eigen::Vector2d> rings_along_profile(const std::vector<Eigen::Vector2d>& profile, double short_side) {
  std::vector<Eigen::Vector2d> out;
  for (size_t i = 0; i < profile.size(); ++i) {
    if (i > 0) {
      const Eigen::Vector2d d = profile[i] - profile[i - 1];
      const double shorter = std::min(std::abs(d.x()), std::abs(d.y()));
      // And every 0.25 mm along the spindle, as a rounded wheel's rim: a plane oblique to the spindle meets
      // the wheel in an ellipse's arc, which two rings 10 mm apart took as its chord (0.13 mm shallow at
      // W = 30 on a flat 10 mm rim; black-box testing).
      const double by_short = std::ceil(shorter / std::max(short_side, 1e-6) - 1e-9);
      const double by_length = std::ceil(std::abs(d.x()) / kRimRingStep - 1e-9);
      const int n = static_cast<int>(std::min(1e4, std::max(by_short, by_length)));
      for (int k = 1; k < n; ++k) out.push_back(profile[i - 1] + d * (double(k) / n));
    }
    out.push_back(profile[i]);
  }
  return out;
}

int generator_count(double radius, const SectionOptions& options) {
  const double cos_half = 1.0 - options.chord_tolerance / (2.0 * std::max(radius, 1e-9));
  if (!(cos_half > -1.0 && cos_half < 1.0)) return options.generators;
  const double needed = std::ceil(M_PI / std::acos(cos_half));
  return static_cast<int>(std::clamp(needed, double(options.generators), 100000.0));
}

std::vector<Eigen::Vector2d> generator_table(int n) {
  std::vector<Eigen::Vector2d> t;
  for (int g = 0; g < n; ++g) t.emplace_back(std::cos(2.0 * M_PI * g / n), std::sin(2.0 * M_PI * g / n));
  return t;
}

double distance_bound(const PoseInfo& info, const Wheel& wheel, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - info.pose.centre;
  const double t = d.dot(info.pose.axis);
  const double radial = (d - t * info.pose.axis).norm();
  return std::hypot(std::max(0.0, std::abs(t) - 0.5 * wheel.thickness), std::max(0.0, radial - wheel.radius));
}

std::vector<int> convex_hull_indices(const std::vector<Eigen::Vector2d>& pts) {
  std::vector<int> order(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int i, int j) {
    return pts[i].x() < pts[j].x() || (pts[i].x() == pts[j].x() && pts[i].y() < pts[j].y());
  });
  const size_t n = order.size();
  if (n < 3) return order;
  std::vector<int> h(2 * n);
  auto cross = [&](int o, int a, int b) {
    return (pts[a].x() - pts[o].x()) * (pts[b].y() - pts[o].y()) - (pts[a].y() - pts[o].y()) * (pts[b].x() - pts[o].x());
  };
  size_t k = 0;
  for (size_t i = 0; i < n; ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], order[i]) <= 0) --k;
    h[k++] = order[i];
  }
  for (size_t i = n - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], order[i - 1]) <= 0) --k;
    h[k++] = order[i - 1];
  }
  h.resize(k - 1);
  return h;
}

std::vector<Eigen::Vector2d> convex_hull(const std::vector<Eigen::Vector2d>& pts) {
  std::vector<Eigen::Vector2d> h;
  for (const int i : convex_hull_indices(pts)) h.push_back(pts[size_t(i)]);
  return h;
}

}  // namespace tf::grind::detail
