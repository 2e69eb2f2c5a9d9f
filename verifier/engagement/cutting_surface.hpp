// tiltfield engagement (internal): the cutting surface of a tool of revolution as a meridian profile, and
// the tool frame at a pose, which place the engagement's sample points.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <variant>

#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/tool.hpp"

namespace tf::engagement {

inline constexpr double kPi = std::numbers::pi;

// cos and sin of a small angle x (radians, |x| <= kSmallTurn): the series to the 7th power, exact to
// about 1e-12 there, and a few multiply-adds where std::sin and std::cos cost a call each.
inline constexpr double kSmallTurn = 0.2;
inline void small_cos_sin(double x, double& c, double& s) {
  const double x2 = x * x;
  c = 1.0 - x2 / 2.0 * (1.0 - x2 / 12.0 * (1.0 - x2 / 30.0));
  s = x * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0)));
}

// a mod 2 pi, as std::fmod gives it (the same value: a - 2 pi is exact for a in [2 pi, 4 pi]), without its
// call for the angles around a ring, which lie below two turns.
inline double wrap_turn(double a) {
  constexpr double turn = 2.0 * kPi;
  if (a >= 0.0 && a < turn) return a;
  if (a >= turn && a < 2.0 * turn) return a - turn;
  return std::fmod(a, turn);
}

// std::remainder(a, 2 pi): a itself within half a turn, as it nearly always is for the angle between two
// neighbouring rings' arc ends.
inline double remainder_turn(double a) { return std::abs(a) <= kPi ? a : std::remainder(a, 2.0 * kPi); }

// A point of the profile: radius r and height z above the tip, and the outward normal's radial and axial
// components.
struct ProfilePoint {
  double r, z, nr, nz;
};

// The cutting surface (end form and flutes, not the shank or holder) by arc length s from the tip's
// centre: the end face of a flat or bull end, the ball or torus corner, the flutes.
class Profile {
 public:
  explicit Profile(const Tool& tool) : top_(tool.flute_length), R_(tool.radius()) {
    if (const auto* b = std::get_if<BullCutter>(&tool.cutter)) {
      rc_ = b->corner_radius;
    } else if (std::holds_alternative<BallCutter>(tool.cutter)) {
      rc_ = R_;
    }
    flat_ = R_ - rc_;
    arc_ = 0.5 * kPi * rc_;
    length_ = flat_ + arc_ + std::max(0.0, top_ - rc_);
  }
  double length() const { return length_; }
  // Where one piece of the profile meets the next (arc length s): the end face's rim, the corner's ends.
  // The state of the surface is not smooth across a joint: the normal jumps at a flat end's rim, and the
  // facing value, constant over an end face, starts to turn at a bull corner (so an interpolation across a
  // joint is not to be trusted).
  struct Joint {
    double s = -1.0;    // -1: none
    bool jump = false;  // the normal jumps (a flat end's rim)
  };
  std::array<Joint, 2> joints() const {
    std::array<Joint, 2> j{};
    int n = 0;
    if (flat_ > 0.0) j[n++] = {flat_, rc_ == 0.0};
    if (rc_ > 0.0 && length_ > flat_ + arc_) j[n++] = {flat_ + arc_, false};
    return j;
  }
  ProfilePoint at(double s) const { return at(s, nullptr, 0.0); }
  // The same, given a point of the profile `near` at arc length s_near (a ring's): on the corner, within a
  // small turn of it, the angle's sine and cosine come from its normal by the series.
  ProfilePoint at(double s, const ProfilePoint* near, double s_near) const {
    s = std::clamp(s, 0.0, length_);
    if (s < flat_) return {s, 0.0, 0.0, -1.0};  // end face (flat and bull)
    if (s < flat_ + arc_) {                     // ball or torus corner, angle from the tip's normal
      double sn, cs;
      corner_sin_cos(s, near, s_near, sn, cs);
      return {flat_ + rc_ * sn, rc_ - rc_ * cs, sn, -cs};
    }
    return {R_, rc_ + (s - flat_ - arc_), 1.0, 0.0};  // flutes
  }
  // Area of the band [s0, s1] over the full turn, exact for each piece of the profile, mm^2 (`near` as for
  // at()).
  double band_area(double s0, double s1, const ProfilePoint* near = nullptr, double s_near = 0.0) const {
    double a = 0.0;
    auto piece = [&](double lo, double hi, auto&& antiderivative) {
      const double x0 = std::clamp(s0, lo, hi), x1 = std::clamp(s1, lo, hi);
      if (x1 > x0) a += antiderivative(x1) - antiderivative(x0);
    };
    piece(0.0, flat_, [](double s) { return kPi * s * s; });
    piece(flat_, flat_ + arc_, [&](double s) {
      double sn, cs;
      corner_sin_cos(s, near, s_near, sn, cs);
      return 2.0 * kPi * rc_ * (flat_ * (s - flat_) / rc_ - rc_ * cs);
    });
    piece(flat_ + arc_, length_, [&](double s) { return 2.0 * kPi * R_ * s; });
    return a;
  }
  // The band [s0, s1] (s1 > s0) over the full turn, weighted by each of the Lagrange polynomials through
  // the nodes t[0..n) (t = 0 at s0, 1 at s1), into w[0..n), mm^2: sum_k w_k f_k is the band's area where
  // the engaged fraction of the turn is the polynomial through f_k at t_k. Five-point Gauss-Legendre on
  // each piece of the profile the band meets (r is linear or a short arc of a sine there, the
  // polynomials at most cubic: exact to about 1e-12 of the band).
  void band_weights(double s0, double s1, const double* t, int n, double* w) const {
    static constexpr double kX[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                     0.9061798459386640};
    static constexpr double kW[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                     0.4786286704993665, 0.2369268850561891};
    for (int k = 0; k < n; ++k) w[k] = 0.0;
    const double cuts[] = {s0, std::clamp(flat_, s0, s1), std::clamp(flat_ + arc_, s0, s1), s1};
    for (int p = 0; p < 3; ++p) {
      const double a = cuts[p], b = cuts[p + 1];
      if (!(b > a)) continue;
      const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
      for (int q = 0; q < 5; ++q) {
        const double s = mid + kX[q] * half, u = (s - s0) / (s1 - s0), f = 2.0 * kPi * half * kW[q] * at(s).r;
        for (int k = 0; k < n; ++k) {
          double l = 1.0;
          for (int m = 0; m < n; ++m)
            if (m != k) l *= (u - t[m]) / (t[k] - t[m]);
          w[k] += f * l;
        }
      }
    }
  }
  double radius() const { return R_; }

 private:
  // sin and cos of the corner's angle at s (on the corner), from `near`'s normal where it is on the corner
  // within a small turn.
  void corner_sin_cos(double s, const ProfilePoint* near, double s_near, double& sn, double& cs) const {
    const double d = (s - s_near) / rc_;
    if (near && s_near >= flat_ && s_near <= flat_ + arc_ && std::abs(d) <= kSmallTurn) {
      double cd, sd;
      small_cos_sin(d, cd, sd);
      sn = near->nr * cd - near->nz * sd;  // near: (sin, -cos) of its angle
      cs = -near->nz * cd - near->nr * sd;
      return;
    }
    const double th = (s - flat_) / rc_;
    sn = std::sin(th);
    cs = std::cos(th);
  }

  double top_, R_, rc_ = 0.0, flat_ = 0.0, arc_ = 0.0, length_ = 0.0;
};

// Rigid motion of the tool frame (tip at the origin, axis e3) to a pose, with the frame's e1 carried by
// the minimal rotation from a reference so that two frames of one motion agree about the axis' roll.
struct Frame {
  Eigen::Vector3d o, e1, e2, e3;
  Eigen::Vector3d point(double r, double z, double c, double s) const { return o + r * (c * e1 + s * e2) + z * e3; }
  Eigen::Vector3d dir(double nr, double nz, double c, double s) const { return nr * (c * e1 + s * e2) + nz * e3; }
};

inline Frame frame_at(const ToolPose& pose, const Eigen::Vector3d& e1_hint) {
  Frame f;
  f.o = pose.tip;
  f.e3 = pose.axis.normalized();
  Eigen::Vector3d e1 = e1_hint - e1_hint.dot(f.e3) * f.e3;
  if (e1.norm() < 1e-9) e1 = f.e3.unitOrthogonal();
  f.e1 = e1.normalized();
  f.e2 = f.e1.cross(f.e3);  // (n, f, a) is left-handed: angles run clockwise seen from the spindle
  return f;
}

}  // namespace tf::engagement
