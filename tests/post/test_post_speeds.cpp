// The speeds a program asks for, read from what it writes: under TCP F is the tip's speed and the post
// slows it where the axes would exceed their top speed; under G93 F times the block as written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "post_fixture.hpp"
#include "tiltfield/core/kinematics.hpp"

namespace {

using namespace post_test;

// What the controller reads: the axis words to 4 decimals, F to 2 (or as many as a small feed needs).
double written(double v, double scale) { return std::round(v * scale) / scale; }

// Where the axis turns fast about a tip that moves little, no rotary exceeds max_rotary_feed, timed as
// written (black-box testing: C at 44 000 deg/min of a machine's 1 800).
TEST(PostTcpFeed, TheRotariesKeepTheirTopSpeedAsWritten) {
  const tf::PostJob job = job_for("table-table-ac");
  tf::OrientedPath path = impeller_like_path(40);
  for (size_t i = 20; i < path.rows.size(); ++i) path.rows[i].axis = polar_axis(35.0, 60.0);  // a sharp turn
  tf::PostOptions opt;
  opt.dialect = tf::Dialect::Tcp;
  const tf::Program prog = tf::post_program(path, job, opt);
  size_t turning = 0;
  for (size_t k = 1; k < prog.blocks.size(); ++k) {
    const tf::Block &a = prog.blocks[k - 1], &b = prog.blocks[k];
    if (!a.tcp || !b.tcp || b.motion != tf::Motion::Linear || b.feed_mode != tf::FeedMode::PerMinute) continue;
    const auto w = [](double v) { return written(v, 1e4); };
    const double tip = Eigen::Vector3d(w(b.target.x) - w(a.target.x), w(b.target.y) - w(a.target.y),
                                       w(b.target.z) - w(a.target.z)).norm();
    const double rot = std::max({std::abs(w(b.target.a) - w(a.target.a)), std::abs(w(b.target.b) - w(a.target.b)),
                                 std::abs(w(b.target.c) - w(a.target.c))});
    if (rot < 1e-6) continue;
    ++turning;
    const double f = b.feed >= 0.01 ? written(b.feed, 1e2) : b.feed;
    // A block whose tip does not move as written reads F as degrees a minute (a rotary-only move).
    const double minutes = tip > 0 ? tip / f : rot / f;
    EXPECT_LE(rot / minutes, job.machine.max_rotary_feed * (1 + 1e-3)) << "block " << k;
  }
  EXPECT_GT(turning, 0u);
}

// Under TCP the linear axes follow the tilting table on arcs: a turn of A by 85 deg in one block (the
// axis on a great circle) with the tip 130 mm from A's centre drives Y and Z 10 % faster than their
// ends' chord says. Judged on the interpolation
// the controller runs (tip and rotaries linear), sampled finely: no instant above max_feed.
TEST(PostTcpFeed, TheLinearAxesKeepTheirTopSpeedAlongTheirArcs) {
  const tf::PostJob job = job_for("table-table-ac");
  tf::OrientedPath path;
  for (int i = 0; i < 8; ++i) {
    tf::OrientedRow row;
    row.p = {0.2 * i, 150.0, 20.0};
    row.axis = i < 4 ? polar_axis(40.0, -90.0) : polar_axis(45.0, 90.0);  // A turns between rows 3 and 4
    path.rows.push_back(row);
  }
  tf::PostOptions opt;
  opt.dialect = tf::Dialect::Tcp;
  const tf::Program prog = tf::post_program(path, job, opt);
  const tf::Kinematics kin(job.machine, job.tool.length);
  const auto forward = [&](const tf::Joints& q) { return kin.forward(q); };
  size_t turning = 0;
  for (size_t k = 1; k < prog.blocks.size(); ++k) {
    const tf::Block &a = prog.blocks[k - 1], &b = prog.blocks[k];
    if (!a.tcp || !b.tcp || b.motion != tf::Motion::Linear || b.feed_mode != tf::FeedMode::PerMinute) continue;
    const double rot = std::max({std::abs(b.target.a - a.target.a), std::abs(b.target.c - a.target.c)});
    const Eigen::Vector3d tip0(a.target.x, a.target.y, a.target.z), tip1(b.target.x, b.target.y, b.target.z);
    if (rot < 1.0 || (tip1 - tip0).norm() < 1e-3) continue;
    ++turning;
    const double minutes = (tip1 - tip0).norm() / b.feed;
    const int n = 2000;
    double fastest = 0.0;
    Eigen::Vector3d prev;
    for (int i = 0; i <= n; ++i) {
      const double s = double(i) / n;
      tf::Joints q = a.target;
      q.a += s * (b.target.a - a.target.a), q.c += s * (b.target.c - a.target.c);
      const tf::Joints m = tf::joints_for_tip(forward, q, tip0 + s * (tip1 - tip0));
      const Eigen::Vector3d xyz(m.x, m.y, m.z);
      if (i > 0) fastest = std::max(fastest, (xyz - prev).norm() * n / minutes);
      prev = xyz;
    }
    EXPECT_LE(fastest, job.machine.max_feed * (1 + 1e-3)) << "block " << k << " turning " << rot << " deg";
    EXPECT_GE(fastest, job.machine.max_feed * 0.98) << "block " << k << ": slowed more than the axes need";
  }
  EXPECT_GT(turning, 0u);
}

// A turn about a fixed tip under TCP is a rotary-only move (F in degrees a minute), and the part turns
// under the tip: 150 mm from C's centre, C at 7 200 deg/min drives X and Y at 18 850 mm/min.
TEST(PostTcpFeed, ARotaryOnlyTurnKeepsTheLinearAxesTopSpeed) {
  tf::PostJob job = job_for("table-table-ac");
  job.feed = 20000.0;  // capped by max_feed, then by the axes
  tf::OrientedPath path;
  const Eigen::Vector3d tip(150.0, 0.0, 20.0);
  for (int i = 0; i <= 30; ++i) {
    tf::OrientedRow row;
    row.axis = polar_axis(30.0, 3.0 * i);
    row.p = tip + 3.0 * row.axis;  // the ball's centre over a fixed tip
    path.rows.push_back(row);
  }
  tf::PostOptions opt;
  opt.dialect = tf::Dialect::Tcp;
  const tf::Program prog = tf::post_program(path, job, opt);
  const tf::Kinematics kin(job.machine, job.tool.length);
  const auto forward = [&](const tf::Joints& q) { return kin.forward(q); };
  size_t turning = 0;
  for (size_t k = 1; k < prog.blocks.size(); ++k) {
    const tf::Block &a = prog.blocks[k - 1], &b = prog.blocks[k];
    if (!a.tcp || !b.tcp || b.motion != tf::Motion::Linear || b.feed_mode != tf::FeedMode::PerMinute) continue;
    const auto w = [](double v) { return written(v, 1e4); };
    const Eigen::Vector3d tip0(w(a.target.x), w(a.target.y), w(a.target.z)), tip1(w(b.target.x), w(b.target.y), w(b.target.z));
    const double rot = std::max(std::abs(w(b.target.a) - w(a.target.a)), std::abs(w(b.target.c) - w(a.target.c)));
    if (rot < 1e-6 || (tip1 - tip0).norm() > 0.0) continue;
    ++turning;
    const double minutes = rot / written(b.feed, 1e2);
    EXPECT_LE(rot / minutes, job.machine.max_rotary_feed * (1 + 1e-3)) << "block " << k;
    const int n = 500;
    double fastest = 0.0;
    Eigen::Vector3d prev;
    for (int i = 0; i <= n; ++i) {
      const double s = double(i) / n;
      tf::Joints q = a.target;
      q.a = w(a.target.a) + s * (w(b.target.a) - w(a.target.a));
      q.c = w(a.target.c) + s * (w(b.target.c) - w(a.target.c));
      const tf::Joints m = tf::joints_for_tip(forward, q, tip0);
      const Eigen::Vector3d xyz(m.x, m.y, m.z);
      if (i > 0) fastest = std::max(fastest, (xyz - prev).norm() * n / minutes);
      prev = xyz;
    }
    EXPECT_LE(fastest, job.machine.max_feed * (1 + 1e-3)) << "block " << k << " turning " << rot << " deg";
  }
  EXPECT_GT(turning, 0u);
}

// Under G93 F is 1 / the block's minutes, and the tip moves between the ends as written (4 decimals).
// Through the singular pole with no pole cone, the post splits moves down to a few micrometres, where the
// rounded ends had moved the tip 1 % faster than the feed (black-box testing).
TEST(PostInverseTime, TheTipKeepsItsFeedAsWritten) {
  const tf::PostJob job = job_for("table-table-ac");
  tf::OrientedPath path;
  for (int k = 0; k < 41; ++k) {
    const double t = -20.0 + 40.0 * k / 40.0;
    tf::OrientedRow row;
    row.p = {-10.0 + 20.0 * k / 40.0, 5.0, 3.0};
    row.axis = t < 0 ? polar_axis(-t, 180.0) : polar_axis(t, 90.0);  // in along 180 deg, through the pole, out along 90
    path.rows.push_back(row);
  }
  tf::PostOptions opt;
  opt.dialect = tf::Dialect::Joint;
  opt.pole_tolerance_deg = 0.0;
  const tf::Program prog = tf::post_program(path, job, opt);
  const tf::Kinematics kin(job.machine, job.tool.length);
  const auto w = [](tf::Joints j) {
    for (int k = 0; k < 6; ++k) j.axis(k) = written(j.axis(k), 1e4);
    return j;
  };
  size_t timed = 0;
  for (size_t k = 1; k < prog.blocks.size(); ++k) {
    const tf::Block &a = prog.blocks[k - 1], &b = prog.blocks[k];
    if (b.motion != tf::Motion::Linear || b.feed_mode != tf::FeedMode::InverseTime) continue;
    ++timed;
    const double tip = (kin.forward(w(b.target)).tip - kin.forward(w(a.target)).tip).norm();
    const double minutes = 1.0 / written(b.feed, 1e4);
    EXPECT_LE(tip / minutes, job.feed * (1 + 1e-3)) << "block " << k << ", the tip moving " << tip << " mm";
  }
  EXPECT_GT(timed, 20u);
}

}  // namespace
