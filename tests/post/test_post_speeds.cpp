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

// Every axis as the program writes it (4 decimals).
tf::Joints as_written(tf::Joints j) {
  for (int k = 0; k < 6; ++k) j.axis(k) = written(j.axis(k), 1e4);
  return j;
}

// A TCP program's feed moves (G94 linear blocks under TCP) with their ends as written.
struct TcpMove {
  size_t block;
  tf::Joints a, b;  // programmed joints: the tip and the rotaries
  double feed;      // F as written
};
std::vector<TcpMove> tcp_moves(const tf::OrientedPath& path, const tf::PostJob& job) {
  tf::PostOptions opt;
  opt.dialect = tf::Dialect::Tcp;
  const tf::Program prog = tf::post_program(path, job, opt);
  std::vector<TcpMove> out;
  for (size_t k = 1; k < prog.blocks.size(); ++k) {
    const tf::Block &a = prog.blocks[k - 1], &b = prog.blocks[k];
    if (a.tcp && b.tcp && b.motion == tf::Motion::Linear && b.feed_mode == tf::FeedMode::PerMinute)
      out.push_back({k, as_written(a.target), as_written(b.target), b.feed >= 0.01 ? written(b.feed, 1e2) : b.feed});
  }
  return out;
}

// The linear axes' fastest speed (mm/min) over a TCP block between programmed joints `a` and `b` (tip and
// rotaries, as written) taking `minutes`, on the interpolation the controller runs (tip and rotaries
// linear), sampled in n pieces.
double peak_linear_speed(const tf::Kinematics& kin, const tf::Joints& a, const tf::Joints& b, double minutes, int n) {
  const auto forward = [&](const tf::Joints& q) { return kin.forward(q); };
  double fastest = 0.0;
  Eigen::Vector3d prev;
  for (int i = 0; i <= n; ++i) {
    tf::Joints q = a;
    for (int k = 0; k < 6; ++k) q.axis(k) += double(i) / n * (b.axis(k) - a.axis(k));
    const tf::Joints m = tf::joints_for_tip(forward, q, Eigen::Vector3d(q.x, q.y, q.z));
    const Eigen::Vector3d xyz(m.x, m.y, m.z);
    if (i > 0) fastest = std::max(fastest, (xyz - prev).norm() * n / minutes);
    prev = xyz;
  }
  return fastest;
}

// Where the axis turns fast about a tip that moves little, no rotary exceeds max_rotary_feed, timed as
// written (black-box testing: C at 44 000 deg/min of a machine's 1 800).
TEST(PostTcpFeed, TheRotariesKeepTheirTopSpeedAsWritten) {
  const tf::PostJob job = job_for("table-table-ac");
  tf::OrientedPath path = impeller_like_path(40);
  for (size_t i = 20; i < path.rows.size(); ++i) path.rows[i].axis = polar_axis(35.0, 60.0);  // a sharp turn
  size_t turning = 0;
  for (const TcpMove& m : tcp_moves(path, job)) {
    const size_t k = m.block;
    const tf::Joints &wa = m.a, &wb = m.b;
    const double tip = Eigen::Vector3d(wb.x - wa.x, wb.y - wa.y, wb.z - wa.z).norm();
    const double rot = std::max({std::abs(wb.a - wa.a), std::abs(wb.b - wa.b), std::abs(wb.c - wa.c)});
    if (rot < 1e-6) continue;
    ++turning;
    // A block whose tip does not move as written reads F as degrees a minute (a rotary-only move).
    const double minutes = tip > 0 ? tip / m.feed : rot / m.feed;
    EXPECT_LE(rot / minutes, job.machine.max_rotary_feed * (1 + 1e-3)) << "block " << k;
  }
  EXPECT_GT(turning, 0u);
}

// Under TCP the linear axes follow the tilting table on arcs: a turn of A by 85 deg in one block (the
// axis on a great circle) with the tip 130 mm from A's centre drives Y and Z 10 % faster than their
// ends' chord says. Judged on the interpolation the controller runs (tip and rotaries linear), sampled
// finely: no instant above max_feed.
TEST(PostTcpFeed, TheLinearAxesKeepTheirTopSpeedAlongTheirArcs) {
  const tf::PostJob job = job_for("table-table-ac");
  tf::OrientedPath path;
  for (int i = 0; i < 8; ++i) {
    tf::OrientedRow row;
    row.p = {0.2 * i, 150.0, 20.0};
    row.axis = i < 4 ? polar_axis(40.0, -90.0) : polar_axis(45.0, 90.0);  // A turns between rows 3 and 4
    path.rows.push_back(row);
  }
  const tf::Kinematics kin(job.machine, job.tool.length);
  size_t turning = 0;
  for (const TcpMove& m : tcp_moves(path, job)) {
    const size_t k = m.block;
    const tf::Joints &wa = m.a, &wb = m.b;
    const double rot = std::max({std::abs(wb.a - wa.a), std::abs(wb.c - wa.c)});
    const double tip = Eigen::Vector3d(wb.x - wa.x, wb.y - wa.y, wb.z - wa.z).norm();
    if (rot < 1.0 || tip < 1e-3) continue;
    ++turning;
    const double fastest = peak_linear_speed(kin, wa, wb, tip / m.feed, 2000);
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
  const tf::Kinematics kin(job.machine, job.tool.length);
  size_t turning = 0;
  for (const TcpMove& m : tcp_moves(path, job)) {
    const size_t k = m.block;
    const tf::Joints &wa = m.a, &wb = m.b;
    const double rot = std::max(std::abs(wb.a - wa.a), std::abs(wb.c - wa.c));
    if (rot < 1e-6 || Eigen::Vector3d(wb.x - wa.x, wb.y - wa.y, wb.z - wa.z).norm() > 0.0) continue;
    ++turning;
    const double minutes = rot / m.feed;
    EXPECT_LE(rot / minutes, job.machine.max_rotary_feed * (1 + 1e-3)) << "block " << k;
    const double fastest = peak_linear_speed(kin, wa, wb, minutes, 500);
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
  size_t timed = 0;
  for (size_t k = 1; k < prog.blocks.size(); ++k) {
    const tf::Block &a = prog.blocks[k - 1], &b = prog.blocks[k];
    if (b.motion != tf::Motion::Linear || b.feed_mode != tf::FeedMode::InverseTime) continue;
    ++timed;
    const double tip = (kin.forward(as_written(b.target)).tip - kin.forward(as_written(a.target)).tip).norm();
    const double minutes = 1.0 / written(b.feed, 1e4);
    EXPECT_LE(tip / minutes, job.feed * (1 + 1e-3)) << "block " << k << ", the tip moving " << tip << " mm";
  }
  EXPECT_GT(timed, 20u);
}

}  // namespace
