#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "sweep_rows.hpp"
#include "tiltfield/dexel/sweep.hpp"

namespace tf {
namespace {

// Exact membership of p in the swept part, independent of ray_interval: the set of s in [0, 1] with
// p - s d inside the convex part is an interval, intersected constraint by constraint.
bool inside_swept(const SweptPart& sp, const Eigen::Vector3d& p) {
  double lo = 0.0, hi = 1.0;
  auto quad_le0 = [&](double a, double b, double c) {  // a s^2 + b s + c <= 0, a >= 0
    if (a < 1e-15) {
      if (std::abs(b) < 1e-15) { if (c > 0) hi = -1; return; }
      const double r = -c / b;
      if (b > 0) hi = std::min(hi, r); else lo = std::max(lo, r);
      return;
    }
    const double disc = b * b - 4 * a * c;
    if (disc < 0) { hi = -1; return; }
    lo = std::max(lo, (-b - std::sqrt(disc)) / (2 * a));
    hi = std::min(hi, (-b + std::sqrt(disc)) / (2 * a));
  };
  const Eigen::Vector3d w = p - sp.p0;
  if (sp.kind == ToolPart::Kind::Sphere) {
    quad_le0(sp.d.squaredNorm(), -2 * w.dot(sp.d), w.squaredNorm() - sp.radius * sp.radius);
  } else {
    const Eigen::Vector3d& a = sp.axis;
    const double aw = a.dot(w), ad = a.dot(sp.d);
    // 0 <= aw - s ad <= H
    if (std::abs(ad) < 1e-15) { if (aw < 0 || aw > sp.height) return false; }
    else if (ad > 0) { hi = std::min(hi, aw / ad); lo = std::max(lo, (aw - sp.height) / ad); }
    else { lo = std::max(lo, aw / ad); hi = std::min(hi, (aw - sp.height) / ad); }
    const Eigen::Vector3d pw = w - a * aw, pd = sp.d - a * ad;
    quad_le0(pd.squaredNorm(), -2 * pw.dot(pd), pw.squaredNorm() - sp.radius * sp.radius);
  }
  return hi >= lo;
}

TEST(Sweep, RayIntervalsMatchExactMembership) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    ToolPart part;
    part.kind = trial % 2 ? ToolPart::Kind::Cylinder : ToolPart::Kind::Sphere;
    part.radius = 1.0 + std::abs(U(rng)) * 3;
    part.h0 = std::abs(U(rng)) * 2;
    part.h1 = part.h0 + 1 + std::abs(U(rng)) * 8;
    Eigen::Vector3d axis(U(rng), U(rng), U(rng));
    if (trial % 7 == 0) axis = Eigen::Vector3d::UnitZ();  // axis-parallel special cases
    axis.normalize();
    Eigen::Vector3d d(U(rng) * 6, U(rng) * 6, U(rng) * 6);
    if (trial % 5 == 0) d.setZero();
    if (trial % 11 == 0) d = axis * 4.0;  // plunge along the axis
    const SweptPart sp = sweep_part(part, Eigen::Vector3d(U(rng), U(rng), U(rng)), axis, axis.unitOrthogonal(), d);
    for (int r = 0; r < 40; ++r) {
      const int dir = r % 3;
      Eigen::Vector3d o = sp.box.center() + Eigen::Vector3d(U(rng), U(rng), U(rng)).cwiseProduct(sp.box.sizes() / 2);
      o[dir] = 0.0;
      double t0, t1;
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[dir] = 1;
      if (ray_interval(sp, o, dir, t0, t1)) {
        ++checked;
        EXPECT_TRUE(inside_swept(sp, o + e * (0.5 * (t0 + t1))));
        EXPECT_TRUE(inside_swept(sp, o + e * (t0 + 1e-6)));
        EXPECT_TRUE(inside_swept(sp, o + e * (t1 - 1e-6)));
        EXPECT_FALSE(inside_swept(sp, o + e * (t0 - 1e-6)));
        EXPECT_FALSE(inside_swept(sp, o + e * (t1 + 1e-6)));
      } else {
        const double a = sp.box.min()[dir] - 1, b = sp.box.max()[dir] + 1;
        for (double t = a; t <= b; t += 0.01) ASSERT_FALSE(inside_swept(sp, o + e * t)) << "trial " << trial << " t " << t;
      }
    }
  }
  EXPECT_GT(checked, 2000);
}

// Rows of rays in one batch (vectorised, 8 lanes at a time) against the scalar method and exact
// membership, for every case of the kernels: at rest, moving along the rays, across them, slanted to
// them, and the cylinder rows left to the scalar method.
TEST(Sweep, RowBatchesMatchExactMembership) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int checked = 0, misses = 0;
  for (int trial = 0; trial < 300; ++trial) {
    ToolPart part;
    part.kind = trial % 3 == 2 ? ToolPart::Kind::Cylinder : ToolPart::Kind::Sphere;
    part.radius = 0.5 + std::abs(U(rng)) * 3;
    part.h0 = std::abs(U(rng));
    part.h1 = part.h0 + 1 + std::abs(U(rng)) * 4;
    const int dir = trial % 3, u = (dir + 1 + (trial / 3) % 2) % 3;
    Eigen::Vector3d axis = Eigen::Vector3d(U(rng), U(rng), U(rng)).normalized();
    Eigen::Vector3d d(U(rng) * 4, U(rng) * 4, U(rng) * 4);
    switch ((trial / 6) % 4) {
      case 0: d.setZero(); break;
      case 1: d = Eigen::Vector3d::Zero(); d[dir] = U(rng) * 5; break;  // along the rays
      case 2: d[dir] = 0.0; break;                                     // across them
      default: break;                                                  // slanted
    }
    // Cylinder rows the batch leaves to the scalar method: the axis across the rays, the motion along it.
    if (trial % 9 == 5) {
      axis[dir] = 0.0;
      axis.normalize();
    }
    if (trial % 9 == 8) d = axis * U(rng) * 4;
    const SweptPart sp = sweep_part(part, Eigen::Vector3d(U(rng), U(rng), U(rng)) * 10, axis, axis.unitOrthogonal(), d);
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e[dir] = 1;
    for (int row = 0; row < 6; ++row) {
      const int n = 1 + static_cast<int>(std::abs(U(rng)) * 40);
      const double step = sp.box.sizes()[u] / n * (1.0 + 0.5 * std::abs(U(rng)));
      Eigen::Vector3d o = sp.box.center() + Eigen::Vector3d(U(rng), U(rng), U(rng)).cwiseProduct(sp.box.sizes() / 2);
      o[u] = sp.box.min()[u] - step * std::abs(U(rng)) * 3;
      o[dir] = U(rng) * 20;
      std::vector<double> t0(n, 7.0), t1(n, 7.0);
      ray_intervals(sp, o, dir, u, step, n, t0.data(), t1.data());
      for (int i = 0; i < n; ++i) {
        Eigen::Vector3d oi = o;
        oi[u] += step * i;
        double a = 0.0, b = 0.0;
        const bool hit = ray_interval(sp, oi, dir, a, b);
        ASSERT_EQ(hit, t1[i] > t0[i]) << "trial " << trial << " ray " << i;
        if (!hit) {
          ++misses;
          EXPECT_TRUE(t0[i] == std::numeric_limits<double>::infinity() && t1[i] == -t0[i]);
          continue;
        }
        ++checked;
        EXPECT_NEAR(t0[i], a, 1e-9);
        EXPECT_NEAR(t1[i], b, 1e-9);
        EXPECT_TRUE(inside_swept(sp, oi + e * (0.5 * (t0[i] + t1[i]))));
        EXPECT_FALSE(inside_swept(sp, oi + e * (t0[i] - 1e-6)));
        EXPECT_FALSE(inside_swept(sp, oi + e * (t1[i] + 1e-6)));
      }
    }
  }
  EXPECT_GT(checked, 1500);
  EXPECT_GT(misses, 100);
}

// The shadow of a part along a grid axis, row by row: every ray that meets the part lies inside it, and
// where the shadow is exact it is tight (rays just outside miss, rays just inside hit).
TEST(Sweep, ShadowRowsBoundTheHits) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int rows = 0, tilted = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int dir = trial % 3, u = (dir + 1) % 3, v = (dir + 2) % 3;
    ToolPart part;
    part.kind = trial % 4 == 3 ? ToolPart::Kind::Cylinder : ToolPart::Kind::Sphere;
    part.radius = 0.5 + std::abs(U(rng)) * 3;
    part.h1 = 1 + std::abs(U(rng)) * 4;
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    axis[dir] = trial % 8 == 3 ? -1.0 : 1.0;
    if (trial % 8 == 7) axis = Eigen::Vector3d(U(rng), U(rng), U(rng)).normalized();  // not along dir: unknown
    Eigen::Vector3d d(U(rng) * 4, U(rng) * 4, U(rng) * 4);
    if (trial % 5 == 0) d.setZero();
    if (trial % 5 == 1) d[u] = 0.0;  // motion along v only
    if (trial % 5 == 2) d[v] = 0.0;  // along u only
    const SweptPart sp = sweep_part(part, Eigen::Vector3d(U(rng), U(rng), U(rng)) * 5, axis, axis.unitOrthogonal(), d);
    const Shadow sh = make_shadow(sp, dir, u);
    // Exact for spheres and cylinders along dir; a bound for tilted cylinders (the capsule about the axis).
    const bool exact = part.kind == ToolPart::Kind::Sphere || trial % 8 != 7;
    tilted += !exact;
    for (int r = 0; r < 20; ++r) {
      const double cv = sp.box.center()[v] + U(rng) * sp.box.sizes()[v] * 0.6;
      double lo = 0, hi = 0;
      const bool any = shadow_row(sh, cv, lo, hi);
      Eigen::Vector3d o = sp.box.center();
      o[v] = cv;
      o[dir] = -50.0;
      auto hits = [&](double cu) {
        o[u] = cu;
        double t0, t1;
        return ray_interval(sp, o, dir, t0, t1) && t1 - t0 > 1e-9;
      };
      const double a = sp.box.min()[u] - 1.0, b = sp.box.max()[u] + 1.0;
      for (double cu = a; cu <= b; cu += 0.013) {
        if (hits(cu)) {
          ASSERT_TRUE(any && cu >= lo && cu <= hi) << "trial " << trial << " cu " << cu;
        }
      }
      if (!any) continue;
      ++rows;
      EXPECT_FALSE(hits(lo - 1e-6));
      EXPECT_FALSE(hits(hi + 1e-6));
      if (!exact) {
        // The capsule's end caps reach at most r past the cylinder's box.
        EXPECT_GE(lo, sp.box.min()[u] - sp.radius - 1e-9);
        EXPECT_LE(hi, sp.box.max()[u] + sp.radius + 1e-9);
        continue;
      }
      if (hi - lo > 1e-4) {
        EXPECT_TRUE(hits(lo + 1e-5)) << "trial " << trial;
        EXPECT_TRUE(hits(hi - 1e-5)) << "trial " << trial;
      }
    }
  }
  EXPECT_GT(rows, 2000);
  EXPECT_GT(tilted, 20);
}

// Distance from p to a stack of coaxial solids in the tool frame at pose (tip, axis): the ball (a
// sphere of radius R about height R) and the cylinders [h0, h1] x radius, closed form.
struct Body {
  double ball = 0.0;  // ball radius, 0: none
  std::vector<std::array<double, 3>> cylinders;  // h0, h1, radius
  double distance(const ToolPose& pose, const Eigen::Vector3d& p) const {
    const Eigen::Vector3d w = p - pose.tip;
    const double h = w.dot(pose.axis), rho = (w - h * pose.axis).norm();
    double d = std::numeric_limits<double>::infinity();
    if (ball > 0) d = std::max(0.0, std::hypot(rho, h - ball) - ball);
    for (const auto& c : cylinders)
      d = std::min(d, std::hypot(std::max(rho - c[2], 0.0), std::max({c[0] - h, h - c[1], 0.0})));
    return d;
  }
};

// A random point of the solid at pose `pose` at least `margin` inside it.
Eigen::Vector3d point_inside(const Body& body, const ToolPose& pose, double margin, std::mt19937& rng) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const Eigen::Vector3d e1 = pose.axis.unitOrthogonal(), e2 = pose.axis.cross(e1);
  for (;;) {
    const double top = body.cylinders.empty() ? 2 * body.ball : body.cylinders.back()[1];
    double rmax = body.ball;
    for (const auto& c : body.cylinders) rmax = std::max(rmax, c[2]);
    const Eigen::Vector3d p = pose.tip + pose.axis * (U(rng) * top) + e1 * ((2 * U(rng) - 1) * rmax) +
                              e2 * ((2 * U(rng) - 1) * rmax);
    // Inside by at least margin: every point within margin is in the body (sampled on the axis directions).
    bool deep = body.distance(pose, p) == 0.0;
    for (const Eigen::Vector3d& dir : {e1, e2, Eigen::Vector3d(pose.axis)})
      for (double sgn : {-1.0, 1.0}) deep = deep && body.distance(pose, p + sgn * margin * dir) == 0.0;
    if (deep) return p;
  }
}

// The sweep's stated bound, checked both ways against the true motion: a point of the true tool at any
// time, well inside it, lies in the swept parts; a point of a swept part lies within the bound of the
// true tool at some time of the block (times sampled finely enough that the sampling adds < 0.001 mm).
void check_bound(const PoseAt& pose_at, const Body& body, const BlockSweep& bs, bool cutting, double bound) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<const SweptPart*> parts;
  for (const SweptPart& p : bs.parts)
    if (p.cutting == cutting) parts.push_back(&p);
  ASSERT_FALSE(parts.empty());
  for (int i = 0; i < 3000; ++i) {
    const ToolPose pose = pose_at(U(rng));
    const Eigen::Vector3d x = point_inside(body, pose, bound + 1e-6, rng);
    bool in = false;
    for (const SweptPart* p : parts) in = in || inside_swept(*p, x);
    ASSERT_TRUE(in) << "true point not swept, sample " << i;
  }
  // The start and end positions bound the swept region: points just inside their side walls.
  for (int i = 0; i < 4000; ++i) {
    const ToolPose pose = pose_at(i % 2);
    const auto& c = body.cylinders[size_t(U(rng) * body.cylinders.size()) % body.cylinders.size()];
    const double margin = bound + 1e-6 + U(rng) * 0.02;
    if (c[1] - c[0] < 2 * margin) continue;
    const Eigen::Vector3d e1 = pose.axis.unitOrthogonal(), e2 = pose.axis.cross(e1);
    const double ang = U(rng) * 2 * std::numbers::pi, h = c[0] + margin + U(rng) * (c[1] - c[0] - 2 * margin);
    const Eigen::Vector3d x =
        pose.tip + pose.axis * h + (e1 * std::cos(ang) + e2 * std::sin(ang)) * (c[2] - margin);
    bool in = false;
    for (const SweptPart* p : parts) in = in || inside_swept(*p, x);
    ASSERT_TRUE(in) << "wall point not swept, sample " << i << " height " << h;
  }
  constexpr int kTimes = 40000;
  std::vector<ToolPose> poses(kTimes + 1);
  for (int k = 0; k <= kTimes; ++k) poses[k] = pose_at(double(k) / kTimes);
  // The ends of the swept parts' union along random rays: on the boundary of the approximation, where a
  // wrong bound shows.
  Eigen::AlignedBox3d box;
  for (const SweptPart* p : parts) box.extend(p->box);
  double worst = 0.0;
  int ends = 0;
  for (int i = 0; i < 400; ++i) {
    const int dir = i % 3;
    Eigen::Vector3d o = box.min() + (box.max() - box.min()).cwiseProduct(Eigen::Vector3d(U(rng), U(rng), U(rng)));
    o[dir] = box.min()[dir] - 1.0;
    std::vector<std::pair<double, double>> iv;
    for (const SweptPart* p : parts) {
      double t0, t1;
      if (ray_interval(*p, o, dir, t0, t1)) iv.emplace_back(t0, t1);
    }
    std::sort(iv.begin(), iv.end());
    std::vector<double> at;
    for (size_t k = 0; k < iv.size();) {
      double hi = iv[k].second;
      const double lo = iv[k].first;
      while (++k < iv.size() && iv[k].first <= hi) hi = std::max(hi, iv[k].second);
      at.push_back(lo);
      at.push_back(hi);
    }
    for (double t : at) {
      Eigen::Vector3d y = o;
      y[dir] += t;
      double best = std::numeric_limits<double>::infinity();
      for (const ToolPose& q : poses) best = std::min(best, body.distance(q, y));
      worst = std::max(worst, best);
      ++ends;
    }
  }
  EXPECT_GT(ends, 100);
  EXPECT_LE(worst, bound + 1e-3);
}

TEST(Sweep, BlockSubstepsBoundTheError) {
  // A 30 degree tilt while the tip runs a curve: every part's sub-steps hold their own tolerance.
  const Tool tool = [] {
    Tool t;
    t.cutter = BallCutter{3};
    t.flute_length = 12;
    t.shank_radius = 3;
    t.length = 40;
    t.holder = {{10.0, 20.0}};
    return t;
  }();
  SweepOptions opt;
  opt.tolerance = 0.01;
  opt.holder_tolerance = 0.05;
  const auto parts = tool_parts(tool, opt);
  BlockSweep bs;
  const double alpha = 30.0 * std::numbers::pi / 180.0;
  const PoseAt tilt = [&](double tau) {
    return ToolPose{Eigen::Vector3d(10 * tau, 2 * std::sin(std::numbers::pi * tau), 0),
                    Eigen::Vector3d(0, -std::sin(alpha * tau), std::cos(alpha * tau))};
  };
  sweep_block(tilt, parts, opt, bs);
  EXPECT_LE(bs.cutting_error, opt.tolerance);
  EXPECT_LE(bs.holder_error, opt.holder_tolerance);
  EXPECT_GT(bs.cutting_error, 0.3 * opt.tolerance);  // the count is not wastefully high either
  check_bound(tilt, Body{3.0, {{3.0, 12.0, 3.0}}}, bs, true, bs.cutting_error);
  check_bound(tilt, Body{0.0, {{12.0, 40.0, 3.0}, {40.0, 60.0, 10.0}}}, bs, false, bs.holder_error);
  // A straight tip path (as under tool-centre-point control): the tilt alone sets the sub-steps.
  const PoseAt straight = [&](double tau) {
    return ToolPose{Eigen::Vector3d(10 * tau, 0, 0), Eigen::Vector3d(0, -std::sin(alpha * tau), std::cos(alpha * tau))};
  };
  sweep_block(straight, parts, opt, bs);
  EXPECT_LE(bs.cutting_error, opt.tolerance);
  check_bound(straight, Body{3.0, {{3.0, 12.0, 3.0}}}, bs, true, bs.cutting_error);
  check_bound(straight, Body{0.0, {{12.0, 40.0, 3.0}, {40.0, 60.0, 10.0}}}, bs, false, bs.holder_error);
  // The same motion at a tenth of the tolerance still holds it.
  opt.tolerance = 0.001;
  sweep_block(tilt, parts, opt, bs);
  EXPECT_LE(bs.cutting_error, opt.tolerance);
  check_bound(tilt, Body{3.0, {{3.0, 12.0, 3.0}}}, bs, true, bs.cutting_error);
  // The same motion as a rapid: nothing cuts, every part gets the collision-only bound (fewer sub-steps).
  opt.tolerance = 0.01;
  sweep_block(tilt, parts, opt, bs);
  const size_t feed_parts = bs.parts.size();
  sweep_block(tilt, parts, opt, bs, true);
  EXPECT_EQ(bs.cutting_error, 0.0);
  EXPECT_LE(bs.holder_error, opt.holder_tolerance);
  EXPECT_LT(bs.parts.size(), feed_parts);
  check_bound(tilt, Body{3.0, {{3.0, 12.0, 3.0}}}, bs, true, bs.holder_error);
  check_bound(tilt, Body{0.0, {{12.0, 40.0, 3.0}, {40.0, 60.0, 10.0}}}, bs, false, bs.holder_error);
  // A pure translation is one exact step of whole parts.
  sweep_block([&](double tau) { return ToolPose{Eigen::Vector3d(10 * tau, 0, 0), Eigen::Vector3d::UnitZ()}; }, parts,
              opt, bs);
  EXPECT_EQ(bs.substeps, 1);
  EXPECT_EQ(bs.parts.size(), parts.size());
  EXPECT_DOUBLE_EQ(bs.cutting_error, 0.0);
  EXPECT_NEAR(bs.tip_length, 10.0, 1e-12);
}

TEST(Sweep, ArcInterpolation) {
  Block b;
  b.motion = Motion::ArcCCW;
  b.target = {0, 10, 0};
  b.arc_center = {0, 0, 0};
  const Joints from{10, 0, 0};
  const Joints mid = interpolate_block(from, b, 0.5);
  EXPECT_NEAR(mid.x, 10 * std::cos(std::numbers::pi / 4), 1e-12);
  EXPECT_NEAR(mid.y, 10 * std::sin(std::numbers::pi / 4), 1e-12);
  b.motion = Motion::ArcCW;  // the long way round
  const Joints mid2 = interpolate_block(from, b, 0.5);
  EXPECT_NEAR(mid2.x, -10 * std::cos(std::numbers::pi / 4), 1e-12);
  EXPECT_NEAR(mid2.y, -10 * std::sin(std::numbers::pi / 4), 1e-12);
  b.target = {10, 0, 5};  // full helix turn
  const Joints q = interpolate_block(from, b, 0.25);
  EXPECT_NEAR(q.y, -10, 1e-12);
  EXPECT_NEAR(q.z, 1.25, 1e-12);
}

}  // namespace
}  // namespace tf
