// Kinematics: round trips for every machine type, the two solutions, the pole, unwinding, limits, and
// agreement with LinuxCNC's xyzac-trt / xyzbc-trt formulas (2.9, as shipped in Debian 12).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "tiltfield/core/kinematics.hpp"

namespace {

using tf::Joints;
using tf::Kinematics;
using tf::KinematicsType;
using tf::MachineSpec;
using tf::ToolPose;

constexpr double kDeg = M_PI / 180.0;

MachineSpec machine(KinematicsType k) {
  MachineSpec m;
  m.kinematics = k;
  m.pivot = {12.5, -7.25, 30.0};
  m.tilt_offset = {3.0, 20.0, -10.0};
  m.head_pivot_length = 150.0;
  m.table_center = {-40.0, 25.0, 5.0};
  return m;
}

const KinematicsType kFiveAxis[] = {KinematicsType::TableTableAC, KinematicsType::TableTableBC,
                                    KinematicsType::HeadTableBC, KinematicsType::HeadHeadAC};

double tilt(const Joints& j, KinematicsType k) {
  return (k == KinematicsType::TableTableAC || k == KinematicsType::HeadHeadAC) ? j.a : j.b;
}
void set_tilt(Joints& j, KinematicsType k, double v) {
  ((k == KinematicsType::TableTableAC || k == KinematicsType::HeadHeadAC) ? j.a : j.b) = v;
}

double wrap180(double d) { return d - 360.0 * std::round(d / 360.0); }

double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) / kDeg;
}

TEST(Kinematics, RoundTripEveryMachineType) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pos(-200, 200), tilt_d(-110, 110), c_d(-720, 720);
  for (KinematicsType k : kFiveAxis) {
    const Kinematics kin(machine(k), 87.5);
    for (int n = 0; n < 2000; ++n) {
      Joints j{pos(rng), pos(rng), pos(rng)};
      set_tilt(j, k, tilt_d(rng));
      j.c = c_d(rng);
      if (std::abs(tilt(j, k)) < 0.05) continue;  // the pole has its own test
      const ToolPose pose = kin.forward(j);
      ASSERT_NEAR(pose.axis.norm(), 1.0, 1e-12);
      Joints prev = j;
      prev.c += 37.0;  // unwinding toward a previous value near the true one
      const auto sols = kin.inverse(pose, prev);
      ASSERT_EQ(sols.size(), 2u) << to_string(k);
      bool found_original = false;
      for (const Joints& s : sols) {
        const ToolPose back = kin.forward(s);
        EXPECT_LT((back.tip - pose.tip).norm(), 1e-9) << to_string(k);
        EXPECT_LT((back.axis - pose.axis).norm(), 1e-9) << to_string(k);
        EXPECT_LE(std::abs(s.c - prev.c), 180.0 + 1e-9);  // unwound toward prev
        if (std::abs(tilt(s, k) - tilt(j, k)) < 1e-9 && std::abs(s.c - j.c) < 1e-9) {
          found_original = true;
          EXPECT_NEAR(s.x, j.x, 1e-9);
          EXPECT_NEAR(s.y, j.y, 1e-9);
          EXPECT_NEAR(s.z, j.z, 1e-9);
        }
      }
      EXPECT_TRUE(found_original) << to_string(k) << " n=" << n;
      // The two solutions are the mirror pair: tilt negated, C turned by half a turn.
      EXPECT_NEAR(wrap180(tilt(sols[0], k) + tilt(sols[1], k)), 0.0, 1e-9);
      EXPECT_NEAR(std::abs(wrap180(sols[0].c - sols[1].c)), 180.0, 1e-9);
      // The nearest one is the original (prev differs from it only by 37 deg of C).
      const auto near = kin.inverse_nearest(pose, prev);
      ASSERT_TRUE(near);
      EXPECT_NEAR(near->c, j.c, 1e-9);
    }
  }
}

TEST(Kinematics, ZeroRotariesPutTheSpindleNoseAtTipPlusGauge) {
  for (KinematicsType k : kFiveAxis) {
    const Kinematics kin(machine(k), 60.0);
    const auto j = kin.inverse_nearest(ToolPose{{1, 2, 3}, {0, 0, 1}}, Joints{});
    ASSERT_TRUE(j);
    if (k == KinematicsType::HeadHeadAC) {
      EXPECT_NEAR(j->x, 1, 1e-12);
      EXPECT_NEAR(j->y, 2, 1e-12);
      EXPECT_NEAR(j->z, 63, 1e-12);
    }
    EXPECT_NEAR(kin.forward(*j).tip.z(), 3, 1e-12);
  }
  const Kinematics xyz(machine(KinematicsType::XYZ), 60.0);
  const auto j = xyz.inverse_nearest(ToolPose{{1, 2, 3}, {0, 0, 1}}, Joints{});
  ASSERT_TRUE(j);
  EXPECT_EQ(j->z, 3.0);  // 3-axis programs carry the tool tip
  EXPECT_TRUE(xyz.inverse(ToolPose{{1, 2, 3}, Eigen::Vector3d(0.1, 0, 1).normalized()}, Joints{}).empty());
}

// LinuxCNC's trt kinematics, written from its documented formulas (trtfuncs.c, inverse: world pose with
// the tool-length offset applied along world Z -> joints).
Joints linuxcnc_xyzac_inverse(const Eigen::Vector3d& w, double a, double c, const MachineSpec& m, double tool) {
  const double sa = std::sin(a * kDeg), ca = std::cos(a * kDeg), sc = std::sin(c * kDeg), cc = std::cos(c * kDeg);
  const Eigen::Vector3d r = m.pivot;
  const double dy = m.tilt_offset.y(), dz = m.tilt_offset.z() + tool;
  const Eigen::Vector3d p = w - r;
  Joints j;
  j.x = cc * p.x() - sc * p.y() + r.x();
  j.y = sc * ca * p.x() + cc * ca * p.y() - sa * p.z() - ca * dy + sa * dz + dy + r.y();
  j.z = sc * sa * p.x() + cc * sa * p.y() + ca * p.z() - sa * dy - ca * dz + dz + r.z();
  j.a = a;
  j.c = c;
  return j;
}

Joints linuxcnc_xyzbc_inverse(const Eigen::Vector3d& w, double b, double c, const MachineSpec& m, double tool) {
  const double sb = std::sin(b * kDeg), cb = std::cos(b * kDeg), sc = std::sin(c * kDeg), cc = std::cos(c * kDeg);
  const Eigen::Vector3d r = m.pivot;
  const double dx = m.tilt_offset.x(), dz = m.tilt_offset.z() + tool;
  const double dpx = -cb * dx - sb * dz + dx, dpz = sb * dx - cb * dz + dz;
  const Eigen::Vector3d p = w - r;
  Joints j;
  j.x = cc * cb * p.x() - sc * cb * p.y() + sb * p.z() + dpx + r.x();
  j.y = sc * p.x() + cc * p.y() + r.y();
  j.z = -cc * sb * p.x() + sc * sb * p.y() + cb * p.z() + dpz + r.z();
  j.b = b;
  j.c = c;
  return j;
}

TEST(Kinematics, TableTableMatchesLinuxCncTrtKins) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> pos(-100, 100), ang(-179, 179);
  const double L = 72.0;
  for (KinematicsType k : {KinematicsType::TableTableAC, KinematicsType::TableTableBC}) {
    const MachineSpec m = machine(k);
    const Kinematics kin(m, L);
    for (int n = 0; n < 500; ++n) {
      Joints j{pos(rng), pos(rng), pos(rng)};
      set_tilt(j, k, ang(rng));
      j.c = ang(rng);
      const ToolPose pose = kin.forward(j);
      // LinuxCNC with G43 (tool length L along world Z) and tool-offset = L gives the same joints.
      const Eigen::Vector3d world = pose.tip + L * Eigen::Vector3d::UnitZ();
      const Joints ref = k == KinematicsType::TableTableAC ? linuxcnc_xyzac_inverse(world, j.a, j.c, m, L)
                                                           : linuxcnc_xyzbc_inverse(world, j.b, j.c, m, L);
      EXPECT_NEAR(ref.x, j.x, 1e-9);
      EXPECT_NEAR(ref.y, j.y, 1e-9);
      EXPECT_NEAR(ref.z, j.z, 1e-9);
    }
    // Sign of the rotations: positive A tilts the tool toward +Y of the part; positive B toward -X.
    Joints t;
    set_tilt(t, k, 30.0);
    const Eigen::Vector3d axis = kin.forward(t).axis;
    if (k == KinematicsType::TableTableAC) EXPECT_GT(axis.y(), 0.4);
    else EXPECT_LT(axis.x(), -0.4);
  }
}

TEST(Kinematics, TwoSolutionChoiceRespectsLimits) {
  MachineSpec m = machine(KinematicsType::TableTableAC);
  m.limits['A'] = {-10.0, 110.0};
  const Kinematics kin(m, 50.0);
  Joints j;
  j.a = -45.0;
  j.c = 30.0;
  const ToolPose pose = Kinematics(machine(KinematicsType::TableTableAC), 50.0).forward(j);
  const auto sols = kin.inverse(pose, j);
  ASSERT_EQ(sols.size(), 1u);
  EXPECT_NEAR(sols[0].a, 45.0, 1e-9);
  EXPECT_NEAR(std::abs(wrap180(sols[0].c - 30.0)), 180.0, 1e-9);
  // The nearest solution would be the original, but it is out of limits.
  EXPECT_NEAR(kin.inverse_nearest(pose, j)->a, 45.0, 1e-9);
  // Out of reach entirely: a tilt beyond 110 deg either way.
  Joints far;
  far.a = 130.0;
  EXPECT_FALSE(kin.inverse_nearest(Kinematics(machine(KinematicsType::TableTableAC), 50.0).forward(far), Joints{}));
}

TEST(Kinematics, SingularPoleHoldsC) {
  for (KinematicsType k : kFiveAxis) {
    const Kinematics kin(machine(k), 40.0);
    Joints prev;
    prev.c = 123.0;
    // Exactly at the pole: one solution, C held, tip exact.
    const ToolPose at{{5, -3, 2}, {0, 0, 1}};
    auto sols = kin.inverse(at, prev);
    ASSERT_EQ(sols.size(), 1u);
    EXPECT_EQ(sols[0].c, 123.0);
    EXPECT_NEAR(tilt(sols[0], k), 0.0, 1e-12);
    EXPECT_LT((kin.forward(sols[0]).tip - at.tip).norm(), 1e-9);
    // Within the pole tolerance: C still held, axis error at most the tolerance, tip exact.
    tf::InverseOptions opt;
    opt.pole_tolerance_deg = 0.5;
    const Eigen::Vector3d near_axis(std::sin(0.3 * kDeg) * std::cos(1.0), std::sin(0.3 * kDeg) * std::sin(1.0),
                                    std::cos(0.3 * kDeg));
    sols = kin.inverse(ToolPose{at.tip, near_axis}, prev, opt);
    ASSERT_EQ(sols.size(), 1u);
    EXPECT_EQ(sols[0].c, 123.0);
    const ToolPose back = kin.forward(sols[0]);
    EXPECT_LE(angle_deg(back.axis, near_axis), 0.3 + 1e-9);
    EXPECT_LT((back.tip - at.tip).norm(), 1e-9);
    // Outside the tolerance the exact solutions come back.
    opt.pole_tolerance_deg = 0.1;
    sols = kin.inverse(ToolPose{at.tip, near_axis}, prev, opt);
    ASSERT_EQ(sols.size(), 2u);
    for (const auto& s : sols) EXPECT_LT(angle_deg(kin.forward(s).axis, near_axis), 1e-9);
  }
}

TEST(Kinematics, UnwindsContinuousCAcrossTheHalfTurn) {
  for (KinematicsType k : kFiveAxis) {
    const Kinematics kin(machine(k), 40.0);
    // The axis circles the pole three times at 30 deg tilt: C must run on monotonically past +-180.
    Joints prev;
    set_tilt(prev, k, 30.0);
    prev.c = 0.0;
    prev = *kin.inverse_nearest(kin.forward(prev), prev);
    const double start_c = prev.c;
    for (int step = 1; step <= 3 * 72; ++step) {
      Joints truth;
      set_tilt(truth, k, 30.0);
      truth.c = start_c + 5.0 * step;
      truth.x = 10.0;
      const ToolPose pose = kin.forward(truth);
      const auto j = kin.inverse_nearest(pose, prev);
      ASSERT_TRUE(j);
      EXPECT_NEAR(j->c - prev.c, 5.0, 1e-9) << to_string(k) << " step " << step;
      EXPECT_NEAR(tilt(*j, k), 30.0, 1e-9);
      prev = *j;
    }
    EXPECT_NEAR(prev.c, start_c + 1080.0, 1e-6);
  }
}

TEST(Kinematics, LimitedCUnwindsWithinItsRange) {
  MachineSpec m = machine(KinematicsType::TableTableBC);
  m.limits['C'] = {-200.0, 200.0};
  const Kinematics kin(m, 40.0);
  Joints truth;
  truth.b = 40.0;
  truth.c = 170.0;
  const ToolPose pose = kin.forward(truth);
  Joints prev = truth;
  prev.c = 195.0;
  auto j = kin.inverse_nearest(pose, prev);
  ASSERT_TRUE(j);
  EXPECT_NEAR(j->c, 170.0, 1e-9);
  truth.c = -170.0;  // nearest to 195 would be 190, which is inside [-200, 200]
  j = kin.inverse_nearest(kin.forward(truth), prev);
  ASSERT_TRUE(j);
  EXPECT_NEAR(j->c, 190.0, 1e-9);
  truth.c = -150.0;  // 210 is outside: the mirror solution (B -40, C 30) is nearer than C -150
  j = kin.inverse_nearest(kin.forward(truth), prev);
  ASSERT_TRUE(j);
  EXPECT_TRUE(kin.within_limits(*j));
  EXPECT_LT((kin.forward(*j).axis - kin.forward(truth).axis).norm(), 1e-9);
}

}  // namespace
