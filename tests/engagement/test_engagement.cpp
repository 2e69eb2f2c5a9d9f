// Engagement angles, area and depths against closed forms: slotting, half immersion on both
// sides, a ball end at a depth, two pairs where the tool crosses an earlier slot, and a plunge.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "moves.hpp"
#include "tiltfield/dexel/verify.hpp"
#include "tiltfield/engagement/engagement.hpp"

namespace tf {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = 180.0 / kPi;

Tool make_tool(Cutter cutter) {
  Tool t;
  t.cutter = cutter;
  t.flute_length = 20.0;
  t.shank_radius = 5.0;
  t.length = 40.0;
  t.holder = {{12.0, 30.0}};
  return t;
}

Scene box_scene(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Tool& tool) {
  Scene s;
  s.stock.kind = Stock::Kind::Box;
  s.stock.box = {lo, hi};
  s.tool = tool;
  return s;
}

VerifyReport run(const Scene& scene, const test::Moves& moves, double resolution = 0.1, bool keep_pairs = false) {
  VerifyOptions o;
  o.resolution = resolution;
  EngagementOptions eo;
  eo.keep_pairs = keep_pairs;
  o.engagement = engagement_probe(eo);
  return verify_program(scene, moves.program(), forward_xyz, o).report;
}

// Relative tolerance: 1 % of the closed form (angles: of the engaged span).
void expect_within(double value, double expected, double scale, const char* what) {
  EXPECT_NEAR(value, expected, 0.01 * scale) << what;
}

constexpr double R = 5.0, ap = 2.0, L = 20.0;

// Joint values -> pose of a ball end of radius R leaning `deg` back in the x-z plane: the ball's lowest
// point at the programmed X Y Z (its centre R above it, the tip R from the centre along the tilted axis).
ForwardFn leaning_ball(double deg) {
  const double lean = deg * kPi / 180.0;
  return [lean](const Joints& j) {
    const Eigen::Vector3d axis(-std::sin(lean), 0.0, std::cos(lean));
    const Eigen::Vector3d centre(j.x, j.y, j.z + R);
    return ToolPose{centre - R * axis, axis};
  };
}

// Box 0..100 x -20..20 x 0..10; the tool enters from x = -10 at tip height 10 - depth and cuts to x = 50.
test::Moves slot_program(double y, double depth) {
  return test::Moves().rapid({-10, y, 10.0 - depth}).line({.x = 30}, 600).line({.x = 50});
}

// A flat end R5 along a G2 arc at radius 24 about a round boss of radius 20, 1 mm into it: climb milling,
// engaged from 180 - acos((24^2 + 5^2 - 20^2) / (2 24 5)) = 146.88 deg to 180 at every point of the arc.
// The feed direction is the arc's tangent at the block's end; a chord over the arc's last quarter had
// turned it by an eighth of the sweep (a quarter turn: entry 158.2, area 19.0 for 28.8 mm2, black-box
// testing).
TEST(Engagement, AlongAnArcTheFeedIsTheTangent) {
  Scene s;
  s.stock.kind = Stock::Kind::Cylinder;
  s.stock.cylinder = {{0, 0, 0}, {0, 0, 1}, 20.0, 20.0};
  s.tool = make_tool(FlatCutter{R});
  const double rp = 24.0, entry = 180.0 - std::acos((rp * rp + R * R - 400.0) / (2 * rp * R)) * kDeg;
  for (const double sweep : {10.0, 90.0, 180.0}) {
    const double end = (90.0 - sweep) / kDeg;  // clockwise from the top (0, 24)
    const test::Moves m = test::Moves().rapid({-30, rp, 10}).line({.x = 0}, 600).arc(
        {.x = rp * std::cos(end), .y = rp * std::sin(end)}, 0, 0, true);
    const VerifyReport r = run(s, m);
    ASSERT_EQ(r.per_block.size(), 3u);
    const Engagement& line = r.per_block[1].engagement, &arc = r.per_block[2].engagement;
    EXPECT_NEAR(line.entry_deg, entry, 0.5) << sweep;
    EXPECT_NEAR(arc.entry_deg, entry, 0.5) << sweep;
    EXPECT_NEAR(arc.exit_deg, 180.0, 0.5) << sweep;
    EXPECT_NEAR(arc.area_mm2, line.area_mm2, 0.01 * line.area_mm2) << sweep;
  }
}

TEST(Engagement, FlatSlotting180) {
  const Scene s = box_scene({0, -20, 0}, {100, 20, 10}, make_tool(FlatCutter{R}));
  const VerifyReport r = run(s, slot_program(0.0, ap));
  ASSERT_EQ(r.per_block.size(), 3u);
  const BlockResult& b = r.per_block.back();
  const Engagement& e = b.engagement;
  std::cout << "slot: entry " << e.entry_deg << " exit " << e.exit_deg << " area " << e.area_mm2 << " ap "
            << e.axial_depth_mm << " ae " << e.radial_width_mm << " removed " << b.removed_mm3 << "\n";
  expect_within(e.entry_deg, 0.0, 180.0, "entry");
  expect_within(e.exit_deg, 180.0, 180.0, "exit");
  expect_within(e.area_mm2, kPi * R * ap, kPi * R * ap, "area (half the cylinder's side)");
  expect_within(e.axial_depth_mm, ap, ap, "axial depth");
  expect_within(e.radial_width_mm, 2 * R, 2 * R, "radial width");
  EXPECT_EQ(e.max_pairs, 1);
  // Steady state: the block removes a 2R x ap x L box; at F600 the 20 mm take 1/30 min.
  expect_within(b.removed_mm3, 2 * R * ap * L, 2 * R * ap * L, "removed volume");
  expect_within(b.mrr(), 2 * R * ap * L * 30.0, 2 * R * ap * L * 30.0, "MRR");
  // The rapid in air and nothing else engaged.
  EXPECT_FALSE(r.per_block[0].engagement.engaged());
}

TEST(Engagement, HalfImmersionConventionalAndClimb) {
  const Tool tool = make_tool(FlatCutter{R});
  // Feed +x, axis +z: n = a x f = +y. Material on +y (left of the feed): conventional (up) milling, 0..90.
  const VerifyReport up = run(box_scene({0, 0, 0}, {100, 20, 10}, tool), slot_program(0.0, ap));
  // Material on -y (right of the feed): climb (down) milling, 90..180.
  const VerifyReport down = run(box_scene({0, -20, 0}, {100, 0, 10}, tool), slot_program(0.0, ap));
  const Engagement& eu = up.per_block.back().engagement;
  const Engagement& ed = down.per_block.back().engagement;
  std::cout << "conventional " << eu.entry_deg << ".." << eu.exit_deg << " area " << eu.area_mm2 << "; climb "
            << ed.entry_deg << ".." << ed.exit_deg << " area " << ed.area_mm2 << "\n";
  expect_within(eu.entry_deg, 0.0, 90.0, "conventional entry");
  expect_within(eu.exit_deg, 90.0, 90.0, "conventional exit");
  expect_within(ed.entry_deg, 90.0, 90.0, "climb entry");
  expect_within(ed.exit_deg, 180.0, 90.0, "climb exit");
  for (const Engagement* e : {&eu, &ed}) {
    expect_within(e->area_mm2, 0.5 * kPi * R * ap, 0.5 * kPi * R * ap, "area");
    expect_within(e->radial_width_mm, R, R, "radial width");
    expect_within(e->axial_depth_mm, ap, ap, "axial depth");
  }
  expect_within(up.per_block.back().removed_mm3, R * ap * L, R * ap * L, "removed, conventional");
  expect_within(down.per_block.back().removed_mm3, R * ap * L, R * ap * L, "removed, climb");
}

TEST(Engagement, BallEndAtDepth) {
  const double d = 2.0;
  const Scene s = box_scene({0, -20, 0}, {100, 20, 10}, make_tool(BallCutter{R}));
  const VerifyReport r = run(s, slot_program(0.0, d));
  const BlockResult& b = r.per_block.back();
  const Engagement& e = b.engagement;
  const double area = kPi * R * d;  // the front half of the spherical zone of height d
  const double width = 2.0 * std::sqrt(2 * R * d - d * d);
  const double segment = R * R * std::acos((R - d) / R) - (R - d) * std::sqrt(2 * R * d - d * d);
  std::cout << "ball: entry " << e.entry_deg << " exit " << e.exit_deg << " area " << e.area_mm2 << " (" << area
            << ") ap " << e.axial_depth_mm << " ae " << e.radial_width_mm << " (" << width << ") removed "
            << b.removed_mm3 << " (" << segment * L << ")\n";
  expect_within(e.entry_deg, 0.0, 180.0, "entry");
  expect_within(e.exit_deg, 180.0, 180.0, "exit");
  expect_within(e.area_mm2, area, area, "area");
  expect_within(e.axial_depth_mm, d, d, "axial depth");
  expect_within(e.radial_width_mm, width, width, "radial width");
  expect_within(b.removed_mm3, segment * L, segment * L, "removed volume");
}

TEST(Engagement, CrossingAnEarlierSlotGivesTwoPairs) {
  // A slot along y at x 33..43, 3 mm deep; the 2 mm deep x-slot ends at x = 30, where its front arc
  // x = 30 + R sin(phi) is in the earlier slot for sin(phi) >= 0.6.
  const Scene s = box_scene({0, -20, 0}, {100, 20, 10}, make_tool(FlatCutter{R}));
  const test::Moves g = test::Moves()
                            .rapid({38, -30, 7})
                            .line({.y = 30}, 600)
                            .rapid({.z = 20})
                            .rapid({.x = -10, .y = 0})
                            .rapid({.z = 8})
                            .line({.x = 30}, 600);
  // Rings 0.25 mm apart, so that the 2 mm depth holds several heights of pairs (the default spacing here
  // is 0.52 mm).
  VerifyOptions o;
  o.resolution = 0.1;
  EngagementOptions eo;
  eo.keep_pairs = true;
  eo.axial_step_mm = 0.25;
  o.engagement = engagement_probe(eo);
  const VerifyReport r = verify_program(s, g.program(), forward_xyz, o).report;
  const Engagement& e = r.per_block.back().engagement;
  const double gap0 = std::asin(0.6) * kDeg, gap1 = 180.0 - gap0;
  std::cout << "two pairs: max_pairs " << e.max_pairs << ", entry " << e.entry_deg << " exit " << e.exit_deg
            << " area " << e.area_mm2 << "\n";
  EXPECT_EQ(e.max_pairs, 2);
  int heights = 0;
  for (size_t k = 0; k + 1 < e.pairs.size(); ++k) {
    EngagementPair p = e.pairs[k], q = e.pairs[k + 1];
    if (p.height_mm != q.height_mm) continue;  // the two pairs of one height are consecutive
    if (p.entry_deg > q.entry_deg) std::swap(p, q);
    ++heights;
    expect_within(p.entry_deg, 0.0, gap0, "first pair entry");
    expect_within(p.exit_deg, gap0, gap0, "first pair exit");
    expect_within(q.entry_deg, gap1, gap0, "second pair entry");
    expect_within(q.exit_deg, 180.0, gap0, "second pair exit");
  }
  EXPECT_GE(heights, 6);  // every sampled height over the 2 mm depth
  expect_within(e.entry_deg, 0.0, 180.0, "summary entry");
  expect_within(e.exit_deg, 180.0, 180.0, "summary exit");
  const double area = R * ap * 2.0 * gap0 / kDeg;
  expect_within(e.area_mm2, area, area, "area of the two pairs");
}

TEST(Engagement, SlotAlongAShoulderSeesTheStepBetweenRings) {
  // The half y < 0 is faced down to z = 8 first; then a slot along y = 0, 4 deep: 0..180 deg below the
  // step (2 mm) and a quarter turn above it (2 mm). The step's height falls between two rings at the
  // default spacing, where the engaged arc narrows at once rather than smoothly.
  const Scene s = box_scene({0, -20, 0}, {100, 20, 10}, make_tool(FlatCutter{R}));
  const test::Moves g = test::Moves()
                            .rapid({-10, -5, 20})
                            .rapid({.z = 8})
                            .line({.x = 110}, 600)
                            .rapid({.z = 20})
                            .rapid({.x = -10, .y = 0})
                            .rapid({.z = 6})
                            .line({.x = 30}, 600)
                            .line({.x = 50});
  const VerifyReport r = run(s, g);
  const Engagement& e = r.per_block.back().engagement;
  std::cout << "slot along a shoulder: entry " << e.entry_deg << " exit " << e.exit_deg << " area " << e.area_mm2
            << " ap " << e.axial_depth_mm << "\n";
  const double area = kPi * R * 2.0 + kPi / 2.0 * R * 2.0;
  expect_within(e.area_mm2, area, area, "area (half a turn 2 mm high, a quarter turn 2 mm high)");
  expect_within(e.axial_depth_mm, 4.0, 4.0, "axial depth");
  expect_within(e.exit_deg - e.entry_deg, 180.0, 180.0, "engaged span");
}

TEST(Engagement, PlungeEngagesTheWholeEndFace) {
  const Scene s = box_scene({0, -20, 0}, {100, 20, 10}, make_tool(FlatCutter{R}));
  const VerifyReport r = run(s, test::Moves().rapid({50, 0, 12}).line({.z = 8}, 100));
  const Engagement& e = r.per_block.back().engagement;
  std::cout << "plunge: entry " << e.entry_deg << " exit " << e.exit_deg << " area " << e.area_mm2 << "\n";
  EXPECT_NEAR(e.angle_deg(), 360.0, 1e-9);
  expect_within(e.area_mm2, kPi * R * R, kPi * R * R, "end face");
  expect_within(r.per_block.back().removed_mm3, kPi * R * R * ap, kPi * R * R * ap, "removed");
}

TEST(Engagement, InverseTimeMrr) {
  // G93: F is 1 / block minutes, so the MRR of the 20 mm slot block is its volume times F.
  const Scene s = box_scene({0, -20, 0}, {100, 20, 10}, make_tool(FlatCutter{R}));
  const VerifyReport r = run(s, test::Moves().rapid({-10, 0, 8}).line({.x = 30}, 600).inverse_time({.x = 50}, 12));
  const BlockResult& b = r.per_block.back();
  EXPECT_EQ(b.feed_mode, FeedMode::InverseTime);
  expect_within(b.mrr(), b.removed_mm3 * 12.0, b.removed_mm3 * 12.0, "G93 MRR");
  expect_within(b.removed_mm3, 2 * R * ap * L, 2 * R * ap * L, "removed volume");
}

TEST(Engagement, ResolutionDoesNotMoveTheAngles) {
  // Refinement makes the angles independent of the lattice: a 30 deg oblique slot at two resolutions.
  const Scene s = box_scene({0, -20, 0}, {100, 40, 10}, make_tool(FlatCutter{R}));
  const test::Moves g = test::Moves().rapid({-10, -5, 8}).line({.x = 20, .y = 12.3205}, 600).line({.x = 40, .y = 23.8675});
  const Engagement a = run(s, g, 0.1).per_block.back().engagement;
  const Engagement b = run(s, g, 0.2).per_block.back().engagement;
  EXPECT_NEAR(a.entry_deg, 0.0, 0.5);
  EXPECT_NEAR(a.exit_deg, 180.0, 0.5);
  EXPECT_NEAR(a.exit_deg, b.exit_deg, 0.5);
  EXPECT_NEAR(a.area_mm2, b.area_mm2, 0.01 * a.area_mm2);
}

}  // namespace
}  // namespace tf

namespace tf {
namespace {

TEST(Engagement, TiltedBallKeepsTheAreaOfItsCap) {
  // A ball end with its axis leaning 30 deg back in the feed plane (a lead angle) cuts the same
  // spherical cap as an upright one: the front half of a zone of height d, area pi R d. The cap lies in
  // the ball's lower hemisphere in the tilted tool frame too (its rim is 4 mm from the centre's vertical).
  const double d = 2.0;
  const Scene s = box_scene({0, -20, 0}, {100, 20, 10}, make_tool(BallCutter{R}));
  const Program p = slot_program(0.0, d).program();
  const ForwardFn tilted = leaning_ball(30.0);
  VerifyOptions o;
  o.resolution = 0.1;
  o.engagement = engagement_probe();
  const VerifyReport r = verify_program(s, p, tilted, o).report;
  const Engagement& e = r.per_block.back().engagement;
  std::cout << "tilted ball: entry " << e.entry_deg << " exit " << e.exit_deg << " area " << e.area_mm2 << "\n";
  expect_within(e.area_mm2, kPi * R * d, kPi * R * d, "area");
  const double segment = R * R * std::acos((R - d) / R) - (R - d) * std::sqrt(2 * R * d - d * d);
  expect_within(r.per_block.back().removed_mm3, segment * L, segment * L, "removed volume");
  // Angles are in the tilted tool frame, where the cap's rim leaves the 0..180 half: a wider arc.
  EXPECT_GT(e.angle_deg(), 180.0);
}

}  // namespace
}  // namespace tf

namespace tf {
namespace {

TEST(Engagement, BullEndSlot) {
  // Bull R5 / r1, 2 mm deep: the front half of the torus corner, pi r ((R - r) pi/2 + r), plus the front
  // half of the flutes up to the top, pi R (ap - r); the bottom face only rubs the floor.
  const double rc = 1.0;
  const Scene s = box_scene({0, -20, 0}, {100, 20, 10}, make_tool(BullCutter{R, rc}));
  const VerifyReport r = run(s, slot_program(0.0, ap));
  const BlockResult& b = r.per_block.back();
  const Engagement& e = b.engagement;
  const double area = kPi * rc * ((R - rc) * kPi / 2 + rc) + kPi * R * (ap - rc);
  const double section = 2 * R * ap - 2 * (rc * rc - kPi * rc * rc / 4);
  std::cout << "bull: entry " << e.entry_deg << " exit " << e.exit_deg << " area " << e.area_mm2 << " (" << area
            << ") removed " << b.removed_mm3 << " (" << section * L << ")\n";
  expect_within(e.entry_deg, 0.0, 180.0, "entry");
  expect_within(e.exit_deg, 180.0, 180.0, "exit");
  expect_within(e.area_mm2, area, area, "area");
  expect_within(e.axial_depth_mm, ap, ap, "axial depth");
  expect_within(e.radial_width_mm, 2 * R, 2 * R, "radial width");
  expect_within(b.removed_mm3, section * L, section * L, "removed volume");
}

// The rings are as far apart as the angle samples at the rim (0.52 mm on these R 5 tools at 6 deg) and the
// area is integrated between them to second order or better: rings four times closer move the ball's,
// the bull end's (whose face and corner meet at a joint the state is not smooth across) and the tilted
// ball's areas by less than 0.3 %, and doubling the refinement steps moves nothing beyond 1e-4.
TEST(Engagement, RingSpacingAndRefinementStepsDoNotMoveTheArea) {
  auto area = [](const Scene& s, const Program& p, const ForwardFn& fwd, double axial_step, int steps) {
    VerifyOptions o;
    o.resolution = 0.1;
    EngagementOptions eo;
    eo.axial_step_mm = axial_step;
    eo.refine_steps = steps;
    eo.max_rings = 1000;
    o.engagement = engagement_probe(eo);
    return verify_program(s, p, fwd, o).report.per_block.back().engagement.area_mm2;
  };
  const Program p = slot_program(0.0, ap).program();
  const Scene ball = box_scene({0, -20, 0}, {100, 20, 10}, make_tool(BallCutter{R}));
  const Scene bull = box_scene({0, -20, 0}, {100, 20, 10}, make_tool(BullCutter{R, 1.0}));
  const ForwardFn leaning = leaning_ball(30.0);
  for (const auto& [s, fwd] : {std::pair<const Scene*, ForwardFn>{&ball, forward_xyz}, {&bull, forward_xyz}, {&ball, leaning}}) {
    const double coarse = area(*s, p, fwd, 0.0, 8), fine = area(*s, p, fwd, 0.13, 8), more = area(*s, p, fwd, 0.0, 16);
    std::cout << "area at the default rings / rings 0.13 mm apart / 16 steps: " << coarse << " / " << fine << " / "
              << more << "\n";
    EXPECT_NEAR(coarse, fine, 3e-3 * fine);
    EXPECT_NEAR(coarse, more, 1e-4 * more);
  }
}

// The probe measures the tool in the spindle: full-width slots by a library's two tools, R 5 and R 2.
TEST(Engagement, FollowsEachBlocksTool) {
  Scene s = box_scene({0, -20, 0}, {100, 20, 10}, make_tool(FlatCutter{R}));
  s.tools = {{1, make_tool(FlatCutter{R})}, {2, make_tool(FlatCutter{2.0})}};
  Program p = test::Moves()
                  .rapid({-10, -8, 10.0 - ap})
                  .line({.x = 30}, 600)
                  .line({.x = 50})
                  .rapid({.z = 12})
                  .rapid({.x = -10, .y = 8})
                  .rapid({.z = 10.0 - ap})
                  .line({.x = 30}, 600)
                  .line({.x = 50})
                  .program();
  for (size_t i = 0; i < p.blocks.size(); ++i) p.blocks[i].tool = i < 3 ? 1 : 2;
  VerifyOptions o;
  o.resolution = 0.1;
  o.engagement = engagement_probe();
  const VerifyReport r = verify_program(s, p, forward_xyz, o).report;
  ASSERT_EQ(r.per_block.size(), 8u);
  expect_within(r.per_block[2].engagement.radial_width_mm, 2 * R, 2 * R, "tool 1's radial width");
  expect_within(r.per_block[7].engagement.radial_width_mm, 4.0, 4.0, "tool 2's radial width");
  expect_within(r.per_block[7].removed_mm3, 4.0 * ap * L, 4.0 * ap * L, "tool 2's removed volume");
  EXPECT_EQ(r.per_block[7].tool, 2);
}

TEST(Engagement, OneProbeAcrossLatticeSpacings) {
  // A probe keeps its sample grid per spacing: used by a fine run and then a coarse one (fewer rings), it
  // must measure the coarse run as a fresh probe does (it once reset rings of the fine grid that the
  // coarse one no longer had).
  const Scene s = box_scene({0, -20, 0}, {100, 20, 10}, make_tool(FlatCutter{R}));
  const Program p = slot_program(0.0, ap).program();
  VerifyOptions o;
  o.engagement = engagement_probe();
  o.resolution = 0.1;
  const VerifyReport fine = verify_program(s, p, forward_xyz, o).report;
  o.resolution = 1.0;
  const VerifyReport reused = verify_program(s, p, forward_xyz, o).report;
  o.engagement = engagement_probe();
  const VerifyReport fresh = verify_program(s, p, forward_xyz, o).report;
  ASSERT_EQ(reused.per_block.size(), fresh.per_block.size());
  EXPECT_GT(fine.per_block.back().engagement.area_mm2, 0.0);
  auto same = [](double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); };  // NaN: not engaged
  for (size_t i = 0; i < fresh.per_block.size(); ++i) {
    EXPECT_EQ(reused.per_block[i].engagement.area_mm2, fresh.per_block[i].engagement.area_mm2) << "block " << i;
    EXPECT_TRUE(same(reused.per_block[i].engagement.exit_deg, fresh.per_block[i].engagement.exit_deg)) << "block " << i;
  }
  EXPECT_GT(fresh.per_block.back().engagement.area_mm2, 0.0);
}

}  // namespace
}  // namespace tf

namespace tf {
namespace {

// A finishing-like pass: a ball R3 only 0.2 mm deep, fed 37 deg off the lattice's axes. The engaged
// surface is the front half of a thin spherical zone (pi R d, 1.9 mm^2) whose rim the rays cross at
// every angle; its width is the zone's chord.
TEST(Engagement, ShallowBallPassObliqueToTheLattice) {
  const double rb = 3.0, d = 0.2, c = std::cos(37.0 / kDeg), sn = std::sin(37.0 / kDeg);
  const Scene s = box_scene({-40, -40, 0}, {60, 60, 10}, make_tool(BallCutter{rb}));
  const test::Moves g =
      test::Moves().rapid({-30 * c, -30 * sn, 10.0 - d}).line({.x = 0.0, .y = 0.0}, 600).line({.x = 20 * c, .y = 20 * sn});
  const Engagement e = run(s, g, 0.05).per_block.back().engagement;
  const double area = kPi * rb * d, width = 2.0 * std::sqrt(2 * rb * d - d * d);
  std::cout << "shallow ball: entry " << e.entry_deg << " exit " << e.exit_deg << " area " << e.area_mm2 << " (" << area
            << ") ae " << e.radial_width_mm << " (" << width << ") ap " << e.axial_depth_mm << "\n";
  EXPECT_NEAR(e.entry_deg, 0.0, 0.5);
  EXPECT_NEAR(e.exit_deg, 180.0, 0.5);
  expect_within(e.area_mm2, area, area, "area");
  expect_within(e.radial_width_mm, width, width, "radial width");
  expect_within(e.axial_depth_mm, d, d, "axial depth");
}

}  // namespace
}  // namespace tf
