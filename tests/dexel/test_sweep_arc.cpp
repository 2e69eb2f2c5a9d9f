// Exact sweeps along planar arcs (sweep_arc.cpp): per-ray intervals against membership computed by brute
// force (the arc sampled densely), shadows that hold every hit, which blocks are taken as arcs, and the
// removed volume of a ball along an arc against Pappus' closed form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "helpers.hpp"
#include "sweep_rows.hpp"
#include "tiltfield/dexel/sweep.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf {
namespace {

constexpr double kArcPi = std::numbers::pi;

// A pose function for a tool of axis e_k (sign `sign`) whose tip runs on the circle (centre c, radius rho)
// in the plane across k, from angle a0 by `turn` (rad), rising by `rise` (a helix when not 0).
PoseAt circle_motion(int k, double sign, const Eigen::Vector3d& c, double rho, double a0, double turn, double rise = 0.0) {
  return [=](double tau) {
    const int u = (k + 1) % 3, v = (k + 2) % 3;
    const double a = a0 + turn * tau;
    Eigen::Vector3d tip = c;
    tip[u] += rho * std::cos(a);
    tip[v] += rho * std::sin(a);
    tip[k] += rise * tau;
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    axis[k] = sign;
    return ToolPose{tip, axis};
  };
}

// Is p within the part swept along the piece, by brute force: the part's centre line sampled at 4001
// points of the piece (k, the arc in the plane across it, the part's z along k); the samples are at most
// rho (pi / 8000)^2 / 8 < 3e-6 mm from the arc between them.
bool inside_arc_sweep(const SweptPart& s, const Eigen::Vector3d& p) {
  const int k = s.arc_axis, u = (k + 1) % 3, v = (k + 2) % 3;
  double best = 1e300;
  for (int i = 0; i <= 4000; ++i) {
    const double a = s.arc_a0 + (s.arc_a1 - s.arc_a0) * i / 4000.0;
    best = std::min(best, std::hypot(p[u] - (s.arc_cu + s.arc_radius * std::cos(a)), p[v] - (s.arc_cv + s.arc_radius * std::sin(a))));
  }
  if (s.kind == ToolPart::Kind::Sphere) return best * best + (p[k] - s.arc_z0) * (p[k] - s.arc_z0) <= s.radius * s.radius;
  return best <= s.radius && p[k] >= s.arc_z0 && p[k] <= s.arc_z1;
}

TEST(SweepArc, RayIntervalsMatchBruteForceMembership) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  // The ball and the flutes (the shank and holder are cylinders like the flutes).
  std::vector<ToolPart> parts = tool_parts(test::ball_tool(2.0, 6.0, 2.0, 12.0, {{6.0, 5.0}}));
  parts.resize(2);
  int rays = 0, hits = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const int k = trial % 3;
    const double rho = 1.0 + 6.0 * (U(rng) + 1.0);  // 1 .. 13 mm, also below the ball's radius... and above
    const double turn = (trial % 2 ? 1.0 : -1.0) * (0.3 + 2.8 * (U(rng) + 1.0));
    PlanarArc arc;
    const PoseAt motion = circle_motion(k, trial % 4 < 2 ? 1.0 : -1.0, Eigen::Vector3d(U(rng), U(rng), U(rng)), rho, U(rng) * kArcPi, turn);
    ASSERT_TRUE(planar_arc(motion, arc)) << trial;
    EXPECT_NEAR(arc.radius, rho, 1e-9);
    EXPECT_NEAR(arc.sweep, turn, 1e-9);
    BlockSweep out;
    sweep_arc(arc, motion(0.0), parts, out);
    EXPECT_EQ(out.cutting_error, 0.0);
    for (const SweptPart& s : out.parts) {
      ASSERT_TRUE(s.arc);
      EXPECT_LE(s.arc_a1 - s.arc_a0, kArcPi / 2 + 1e-12);
      for (int r = 0; r < 3; ++r) {
        const int dir = r % 3;
        // A ray through a random point of the part's box, along grid axis dir.
        Eigen::Vector3d o;
        for (int c = 0; c < 3; ++c) o[c] = s.box.min()[c] + (s.box.max()[c] - s.box.min()[c]) * 0.5 * (U(rng) + 1.0);
        o[dir] = 0.0;
        double t0 = 0, t1 = 0;
        const bool hit = ray_interval(s, o, dir, t0, t1);
        ++rays;
        hits += hit;
        // Sample the ray across the box: inside exactly on [t0, t1] (up to the brute force's own error).
        const double from = s.box.min()[dir] - 0.5, to = s.box.max()[dir] + 0.5;
        for (int i = 0; i <= 60; ++i) {
          const double t = from + (to - from) * i / 60.0;
          Eigen::Vector3d q = o;
          q[dir] = t;
          const bool in = inside_arc_sweep(s, q);
          const bool claimed = hit && t >= t0 && t <= t1;
          if (hit && (std::abs(t - t0) < 1e-3 || std::abs(t - t1) < 1e-3)) continue;
          EXPECT_EQ(in, claimed) << "trial " << trial << " dir " << dir << " t " << t << " [" << t0 << ", " << t1 << "]";
        }
        // The shadow along dir holds every hit.
        if (hit) {
          const int u = (dir + 1) % 3;
          const Shadow sh = make_shadow(s, dir, u);
          double lo = 0, hi = 0;
          ASSERT_TRUE(shadow_row(sh, o[3 - dir - u], lo, hi));
          EXPECT_LE(lo, o[u] + 1e-9);
          EXPECT_GE(hi, o[u] - 1e-9);
        }
      }
    }
  }
  EXPECT_GT(hits, rays / 4);
}

TEST(SweepArc, OnlyPlanarArcsAcrossTheAxis) {
  PlanarArc arc;
  EXPECT_TRUE(planar_arc(circle_motion(2, 1.0, Eigen::Vector3d(1, 2, 3), 5.0, 0.2, 2 * kArcPi), arc));  // a full circle
  EXPECT_NEAR(std::abs(arc.sweep), 2 * kArcPi, 1e-9);
  EXPECT_FALSE(planar_arc(circle_motion(2, 1.0, Eigen::Vector3d::Zero(), 5.0, 0.0, 1.0, 0.5), arc));  // a helix
  // The axis along x while the circle lies in the xy plane: the axis is in the arc's plane.
  const PoseAt in_plane = [](double tau) {
    return ToolPose{Eigen::Vector3d(5 * std::cos(tau), 5 * std::sin(tau), 0.0), Eigen::Vector3d::UnitX()};
  };
  EXPECT_FALSE(planar_arc(in_plane, arc));
  const PoseAt line = [](double tau) { return ToolPose{Eigen::Vector3d(tau, 2 * tau, 0.0), Eigen::Vector3d::UnitZ()}; };
  EXPECT_FALSE(planar_arc(line, arc));
  // A block on such an arc is swept exactly: one sub-step, no bound spent.
  BlockSweep out;
  sweep_block(circle_motion(2, 1.0, Eigen::Vector3d::Zero(), 8.0, 0.0, 1.5), tool_parts(test::ball_tool(3, 10, 3, 20, {{8, 10}})), {}, out);
  EXPECT_EQ(out.substeps, 1);
  EXPECT_EQ(out.cutting_error, 0.0);
  EXPECT_NEAR(out.tip_length, 8.0 * 1.5, 1e-9);
  ASSERT_FALSE(out.parts.empty());
  EXPECT_TRUE(out.parts.front().arc);
}

TEST(SweepArc, BallAlongAnArcRemovesPappusVolume) {
  // Ball R 3, centre on the stock's top (tip 3 below it): a plunge (the lower hemisphere), then a quarter
  // arc of radius 20 about the origin. The arc removes the half tube below the top, (pi R^2 / 2) rho turn
  // (Pappus: the half disc's centroid runs on the arc), plus the front quarter of the end ball, less the
  // front quarter of the start ball, which the plunge took: the two cancel.
  const double R = 3.0, rho = 20.0, turn = kArcPi / 2;
  const Scene s = test::box_scene({-5, -5, 0}, {30, 30, 10}, test::ball_tool(R, 10, R, 20, {{8, 10}}));
  Program p;
  p.start = {rho, 0, 20};
  Block plunge;
  plunge.motion = Motion::Linear;
  plunge.line = 1;
  plunge.feed = 500;
  plunge.target = {rho, 0, 10 - R};
  Block arc = plunge;
  arc.line = 2;
  arc.motion = Motion::ArcCCW;
  arc.target = {0, rho, 10 - R};
  arc.arc_center = {0, 0, 10 - R};
  p.blocks = {plunge, arc};
  VerifyOptions o;
  o.resolution = 0.1;
  const VerifyResult r = verify_program(s, p, forward_xyz, o);
  const double expected = kArcPi * R * R / 2 * rho * turn;
  ASSERT_EQ(r.report.per_block.size(), 2u);
  EXPECT_NEAR(r.report.per_block[1].removed_mm3, expected, 0.005 * expected);
  EXPECT_NEAR(r.report.per_block[0].removed_mm3, 2.0 / 3.0 * kArcPi * R * R * R, 0.005 * 2.0 / 3.0 * kArcPi * R * R * R);
  EXPECT_EQ(r.report.sweep_error_mm, 0.0);
}

}  // namespace
}  // namespace tf
