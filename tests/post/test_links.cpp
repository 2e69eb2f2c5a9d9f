// Links and checked transit moves: a jump across a boss of stock is linked (retract, rapid, approach)
// instead of cut through, the rapids clear the stock by an independent closed-form check, the retract
// lifts only as far as the stock and a fixture next to it need, and the inside test of the stock is right.
#include <gtest/gtest.h>

#include <algorithm>

#include "links_fixture.hpp"
#include "post_fixture.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/machine.hpp"
#include "transit_check.hpp"

namespace {

using namespace links_test;

const Box kBoss = boss_stock_boxes()[1];

tf::PostJob boss_job(const std::string& machine) {
  tf::PostJob job;
  job.machine = tf::read_machine_json(post_test::machine_file(machine));
  job.tool = links_tool();
  job.feed = 1000.0;
  job.stock = boss_stock_mesh();
  job.part_bounds = Eigen::AlignedBox3d(Eigen::Vector3d(-40, -20, 0), Eigen::Vector3d(40, 20, 40));
  return job;
}

// The highest tool tip over the rapid blocks between the first and the last feed block (the links; the
// start and the end go to the transit height whatever the obstacles), part frame.
double highest_link_tip(const tf::Program& prog, const tf::Kinematics& kin) {
  size_t first = prog.blocks.size(), last = 0;
  for (size_t i = 0; i < prog.blocks.size(); ++i)
    if (prog.blocks[i].motion == tf::Motion::Linear) first = std::min(first, i), last = i;
  double z = -1e300;
  for (size_t i = first; i < last; ++i)
    if (prog.blocks[i].motion == tf::Motion::Rapid) z = std::max(z, kin.forward(prog.blocks[i].target).tip.z());
  return z;
}

TEST(Links, JumpAcrossABossIsLinkedAndEveryRapidClearsTheStock) {
  for (const char* machine : {"xyz", "table-table-ac", "head-head-ac"}) {
    SCOPED_TRACE(machine);
    const tf::PostJob job = boss_job(machine);
    const tf::Kinematics kin(job.machine, job.tool.length);
    const tf::Program prog = tf::post_program(two_passes(), job, tf::PostOptions{});
    const double safe_z = job.machine.safe_z;
    EXPECT_FALSE(feed_crosses(prog, kin, kBoss)) << "a feed move through the boss";
    const RapidCheck rc = check_rapids(prog, kin, job.tool, boss_stock_boxes());
    // start: 3 rapids; the link: retract, across (no rise: both retracts are at one height), down; end: 2.
    EXPECT_GE(rc.rapids, 7);
    // The moves between retracts keep half of safe_z (the body's surface points are 0.5 mm apart).
    EXPECT_GT(rc.min_clearance, 0.5 * safe_z - 0.5);
    EXPECT_LT(rc.max_retract_off_axis_deg, 1e-6);
    EXPECT_GT(rc.min_retract_end, safe_z - 0.5);
    // Only as far as needed: just safe_z from the boss' edge (at the part's extent plus safe_z, as
    // without the stock, it would be about 24.5 mm).
    EXPECT_LT(rc.max_retract_end, safe_z + 1.0);
    // Below the transit height over the part's top (40 + safe_z) that links without the check would take.
    const tf::PostJob plain = [&] {
      tf::PostJob j = job;
      j.stock = tf::Mesh();
      return j;
    }();
    const tf::Program unchecked = tf::post_program(two_passes(), plain, tf::PostOptions{});
    EXPECT_LT(highest_link_tip(prog, kin) + 4.0, highest_link_tip(unchecked, kin));
    EXPECT_FALSE(feed_crosses(unchecked, kin, kBoss));
  }
}

TEST(Links, WithoutLinksTheJumpCutsThroughTheBoss) {
  const tf::PostJob job = boss_job("xyz");
  const tf::Kinematics kin(job.machine, job.tool.length);
  tf::PostOptions o;
  o.link_gap_mm = 1e9;
  EXPECT_TRUE(feed_crosses(tf::post_program(two_passes(), job, o), kin, kBoss));
  o.link_gap_mm = 49.0;  // the jump is 50 mm
  EXPECT_FALSE(feed_crosses(tf::post_program(two_passes(), job, o), kin, kBoss));
  EXPECT_DOUBLE_EQ(tf::effective_link_gap(tf::PostOptions{}, job.tool), tf::kLinkGapToolRadii * 3.0);
}

// A tall clamp 16 mm beside the first pass: the holder and shank rise past its top before the retract
// ends, and the clearance to it is safe_z; the same post without the clamp in the job stops lower, within
// safe_z of it (so the check is what lifts it).
TEST(Links, RetractLiftsClearOfAFixtureBesideIt) {
  const Box clamp{{-48, -20, 0}, {-41, 20, 70}};
  const tf::Mesh clamp_mesh = box_mesh(clamp);
  tf::PostJob job = boss_job("xyz");
  job.part_bounds.extend(clamp.lo);
  job.part_bounds.extend(clamp.hi);
  const tf::Kinematics kin(job.machine, job.tool.length);
  const double safe_z = job.machine.safe_z;
  auto retract_ends_near_clamp = [&](const tf::PostJob& j) {
    return check_rapids(tf::post_program(two_passes(), j, tf::PostOptions{}), kin, j.tool, {clamp});
  };
  const RapidCheck without = retract_ends_near_clamp(job);
  EXPECT_LT(without.min_retract_end, safe_z - 1.0);
  job.fixtures = {&clamp_mesh};
  const tf::Program prog = tf::post_program(two_passes(), job, tf::PostOptions{});
  const RapidCheck with = check_rapids(prog, kin, job.tool, {clamp});
  EXPECT_GT(with.min_retract_end, safe_z - 0.5);
  EXPECT_GT(with.min_clearance, 0.5 * safe_z - 0.5);
  EXPECT_GT(check_rapids(prog, kin, job.tool, boss_stock_boxes()).min_clearance, 0.5 * safe_z - 0.5);
  // Still below the part's extent (the clamp's top, 70) plus safe_z, where the retract went before.
  EXPECT_LT(highest_link_tip(prog, kin), 70.0 + safe_z - 5.0);
}

// A head 84 deg off vertical beside the boss (the axis pointing away from it) on a machine without X or Y
// limits: the retract is short, and the rise to the transit height went on along the axis, 1 m sideways
// (black-box testing; limits had stopped it where they exist). Now out along the axis to the full
// retract by rapid, then straight up; the plunge still starts from the short retract.
TEST(Links, AFarTiltedHeadGoesNoFartherSidewaysThanItsFullRetract) {
  const tf::PostJob job = boss_job("head-head-ac");
  ASSERT_EQ(job.machine.limits.count('X'), 0u);
  const tf::Kinematics kin(job.machine, job.tool.length);
  tf::OrientedPath path;
  for (int i = 0; i <= 10; ++i) {
    tf::OrientedRow r;
    r.p = {50.0, -5.0 + i, 20.0};
    r.axis = post_test::polar_axis(84.0, 0.0);
    path.rows.push_back(r);
  }
  const tf::Program prog = tf::post_program(path, job, tf::PostOptions{});
  // The full retract lies safe_z beyond the part's extent along the axis, which here is behind the tip: the
  // tilted tool (the start's turn from A 0 left out) stays within about safe_z of the path sideways.
  double farthest = 0.0, plunge = 0.0;
  for (size_t i = 0; i < prog.blocks.size(); ++i) {
    const tf::Block& b = prog.blocks[i];
    if (std::abs(b.target.a) > 1.0) farthest = std::max(farthest, kin.forward(b.target).tip.x() - 50.0);
    if (b.motion == tf::Motion::Linear && i > 0 && prog.blocks[i - 1].motion == tf::Motion::Rapid && plunge == 0.0)
      plunge = (kin.forward(b.target).tip - kin.forward(prog.blocks[i - 1].target).tip).norm();
  }
  EXPECT_LT(farthest, 2.0 * job.machine.safe_z);
  EXPECT_GT(plunge, 0.5);
  EXPECT_LT(plunge, job.machine.safe_z + 1.0) << "the plunge from the short retract";
}

TEST(Links, StockInsideTestAndCapsuleClearance) {
  const tf::PostJob job = boss_job("xyz");
  const tf::post_detail::TransitChecker check(job);
  ASSERT_TRUE(check.active());
  auto point = [&](const Eigen::Vector3d& p) { return check.capsule_clearance(p, p, 0.0, 100.0); };
  EXPECT_NEAR(point({0, 0, 30}), -10.0, 1e-9);     // in the boss, 10 mm from its sides
  EXPECT_NEAR(point({-30, 5, 10}), -10.0, 1e-9);   // in the plate
  EXPECT_NEAR(point({25, 0, 30}), 10.0, 1e-9);     // above the plate beside the boss (a notch)
  EXPECT_NEAR(point({0, 0, 45}), 5.0, 1e-9);       // above the boss
  EXPECT_NEAR(point({0, 0, 500}), 100.0, 1e-9);    // capped
  // A vertical capsule of radius 2 from z 25 to 35 at x = 15: 5 mm from the boss' side, 5 above the plate.
  EXPECT_NEAR(check.capsule_clearance({15, 0, 25}, {15, 0, 35}, 2.0, 100.0), 3.0, 1e-9);
  // The body capsules enclose the tool: ball and flutes, shank, holder, radii non-decreasing.
  const auto caps = tf::post_detail::body_capsules(job.tool);
  ASSERT_EQ(caps.size(), 3u);
  EXPECT_DOUBLE_EQ(caps[0].h0, 3.0);
  EXPECT_DOUBLE_EQ(caps[2].h1, 100.0);
  EXPECT_DOUBLE_EQ(caps[2].radius, 12.0);
  // The least lift of the first row: the flutes' capsule (radius 3, from 3 mm above the tip) clears the
  // boss' top edge (15 mm across) by safe_z: its foot at 40 + sqrt(23^2 - 15^2) = 57.44, the tip at
  // 54.44, 35.44 above the row's tip at 19.
  const tf::ToolPose row{{-25, -15, 19}, Eigen::Vector3d::UnitZ()};
  const auto lift = check.lowest_lift(row, 1.0, 41.0, 20.0);
  ASSERT_TRUE(lift);
  EXPECT_NEAR(*lift, 40.0 + std::sqrt(23.0 * 23.0 - 15.0 * 15.0) - 3.0 - 19.0, 0.02);
}

// A path that says how its rows are reached (APT's RAPID) is linked where it says and cut everywhere else,
// however long the move: a 40 mm GOTO had been linked over as a jump and nothing cut (black-box testing).
TEST(Links, RowsThePathSaysAreCutOrLinkedAreCutOrLinked) {
  const tf::PostJob job = post_test::job_for("table-table-ac");
  auto rapids_of = [&](const tf::OrientedPath& path) {
    const tf::Program prog = tf::post_program(path, job, tf::PostOptions{});
    return std::count_if(prog.blocks.begin(), prog.blocks.end(), [](const tf::Block& b) { return b.motion == tf::Motion::Rapid; });
  };
  tf::OrientedPath path = post_test::impeller_like_path(100);
  for (size_t i = 10; i < path.rows.size(); ++i) path.rows[i].p.x() += 40.0;
  const auto by_gap = rapids_of(path);
  for (auto& r : path.rows) r.approach = tf::Approach::Cut;
  const auto cut = rapids_of(path);
  EXPECT_LT(cut, by_gap);  // the 40 mm move is cut
  path.rows[50].approach = tf::Approach::Link;  // 3 mm from row 49
  EXPECT_GT(rapids_of(path), cut);
}

}  // namespace

// A tilting table whose Z limit lies below the transit height that clears every turn: the post lowers
// the transit height to the limit and checks each turn there and the move after it (black-box testing:
// the table turned the stock through the tool, and the program was written). The passes on the plate
// need the table tilted 40 deg; the same rapids are checked independently, sampled every 0.5 mm or
// degree, against the stock's boxes.
TEST(Links, ALoweredTransitHeightChecksItsTurns) {
  tf::PostJob job = boss_job("table-table-ac");
  const double s = std::sin(40.0 * M_PI / 180.0), c = std::cos(40.0 * M_PI / 180.0);
  tf::OrientedPath path = two_passes();
  for (tf::OrientedRow& r : path.rows) r.axis = Eigen::Vector3d(0, -s, c);
  const tf::Kinematics kin(job.machine, job.tool.length);
  // Below Z 120 the turn to A -40 at the transit height comes within half of safe_z of the boss: refused.
  for (const double z_limit : {100.0, 110.0}) {
    job.machine.limits['Z'] = {-500.0, z_limit};
    try {
      (void)tf::post_program(path, job, tf::PostOptions{});
      ADD_FAILURE() << "Z limit " << z_limit << ": posted";
    } catch (const tf::JobError& e) {
      EXPECT_NE(std::string(e.what()).find("turning A 0 B 0 C 0 to A -40"), std::string::npos) << e.what();
    }
  }
  for (const double z_limit : {120.0, 140.0, 180.0}) {
    job.machine.limits['Z'] = {-500.0, z_limit};
    const tf::Program prog = tf::post_program(path, job, tf::PostOptions{});
    ASSERT_FALSE(prog.warnings.empty());
    EXPECT_NE(prog.warnings.front().find("each turn there and the move after it checked"), std::string::npos);
    EXPECT_GT(check_rapids(prog, kin, job.tool, boss_stock_boxes()).min_clearance, 0.5 * job.machine.safe_z - 0.5)
        << "Z limit " << z_limit;
  }
}
