// The post-processor where the machine's limits end a configuration: between rows, and at the limit itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>

#include "post_fixture.hpp"
#include "tiltfield/core/kinematics.hpp"

namespace post_limits_test {

using namespace post_test;
using tf::Kinematics;

// head-head-ac with A within +-60 deg and C within +-90 deg.
tf::PostJob limited_head() {
  tf::PostJob job = job_for("head-head-ac");
  job.machine.limits['A'] = {-60.0, 60.0};
  job.machine.limits['C'] = {-90.0, 90.0};
  return job;
}

// n rows, row i's ball centre and axis from row_at(i).
template <class RowAt>
tf::OrientedPath rows(int n, RowAt row_at) {
  tf::OrientedPath path;
  for (int i = 0; i < n; ++i) {
    tf::OrientedRow r;
    std::tie(r.p, r.axis) = row_at(i);
    path.rows.push_back(r);
  }
  return path;
}

// C limited to +-90 deg and the axis turning on around the pole between two rows past where C ends: the
// configuration changes between them, where the limit is reached (retract, turn, re-approach); before,
// neither row could be taken in the other's configuration and the post failed.
TEST(Post, LimitReachedBetweenRowsChangesTheConfigurationThere) {
  const tf::PostJob job = limited_head();
  const tf::OrientedPath path = rows(400, [](int i) { return std::pair{Eigen::Vector3d(i * 0.1, 0, 20), polar_axis(12.0, -9.75 + 0.5 * i)}; });
  const tf::Program prog = tf::post_program(path, job, tf::PostOptions{});
  const Kinematics kin(job.machine, job.tool.length);
  for (const tf::Block& b : prog.blocks) EXPECT_TRUE(kin.within_limits(b.target));
  bool between = false;
  for (const std::string& w : prog.warnings) between |= w.find("where the limits end the move") != std::string::npos;
  EXPECT_TRUE(between);
  for (const Cut& c : cutting_blocks(prog)) EXPECT_LT(tf::rotary_distance(c.from, c.to), 30.0);
}

// A tilt computed at its limit (acos(0.5) is 60.00000000000001 deg; the axis read with 9 decimals)
// is the limit: the row is reached with A at 60, not refused.
TEST(Post, TiltExactlyAtItsLimitIsReached) {
  const tf::PostJob job = limited_head();
  const tf::OrientedPath path = rows(5, [](int i) { return std::pair{Eigen::Vector3d(10.0 + i, 20, 3), Eigen::Vector3d(0, -0.866025404, 0.5)}; });
  const tf::Program prog = tf::post_program(path, job, tf::PostOptions{});
  const Kinematics kin(job.machine, job.tool.length);
  double most = 0;
  for (const tf::Block& b : prog.blocks) {
    EXPECT_TRUE(kin.within_limits(b.target));
    most = std::max(most, std::abs(b.target.a));
  }
  EXPECT_DOUBLE_EQ(most, 60.0);
}

// Under TCP the program holds the tip; the retracts and transits are checked at the machine's joints for
// it (they were written unchecked: machine Z 99.35 on a Z limit of 90, found by black-box testing). With
// the table tilted 30 deg the part's transit height is out of Z's reach at 90: the post refuses, naming the
// point and the axis (lowering that transit alone would leave the turn and the traverse after it unchecked
// near the part). With Z up to 150 every programmed point is within reach.
TEST(Post, TcpTransitsStayWithinTheLinearLimits) {
  tf::PostJob job = job_for("table-table-ac");
  job.machine.output = tf::OutputMode::Tcp;
  job.machine.pivot = Eigen::Vector3d::Zero();
  job.machine.tilt_offset = Eigen::Vector3d::Zero();
  job.machine.safe_z = 20;
  job.part_bounds = Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(20, 20, 10));
  const Eigen::Vector3d axis(0, 0.5, std::sqrt(0.75));
  const tf::OrientedPath path = rows(2, [&](int i) { return std::pair{Eigen::Vector3d(2.0 + 16.0 * i, 10, 13), axis}; });
  job.machine.limits = {{'X', {-100, 100}}, {'Y', {-100, 100}}, {'Z', {-100, 90}}, {'A', {-100, 50}}};
  try {
    tf::post_program(path, job, tf::PostOptions{});
    ADD_FAILURE() << "a transit beyond Z 90 was written";
  } catch (const tf::JobError& e) {
    EXPECT_NE(std::string(e.what()).find("Z 99.352 > 90"), std::string::npos) << e.what();
  }
  job.machine.limits['Z'] = {-100, 150};
  const tf::Program prog = tf::post_program(path, job, tf::PostOptions{});
  const Kinematics kin(job.machine, job.tool.length);
  auto forward = [&](const tf::Joints& j) { return kin.forward(j); };
  double highest = -1e9;
  for (const tf::Block& b : prog.blocks) {
    ASSERT_TRUE(b.tcp);
    const tf::Joints m = tf::joints_for_tip(forward, b.target, Eigen::Vector3d(b.target.x, b.target.y, b.target.z));
    EXPECT_TRUE(kin.within_limits(m)) << "machine Z " << m.z;
    highest = std::max(highest, m.z);
  }
  EXPECT_GT(highest, 99.35);  // the transits at the part's top + safe_z: beyond the first machine's Z 90
}

}  // namespace post_limits_test
