// Collisions (holder in the stock, a rapid through the stock, a fixture touched), a clean program and
// gouges against the design.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "helpers.hpp"
#include "moves.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf {
namespace {

// Ball R 3, flutes to 12, shank R 3 to the gauge length 20, holder R 10 x 30.
Tool short_tool() { return test::ball_tool(3, 12, 3, 20, {{10, 30}}); }

VerifyResult run(const Scene& s, const test::Moves& moves, VerifyOptions o = {}) {
  o.resolution = 0.2;
  return verify_program(s, moves.program(), forward_xyz, o);
}

TEST(Collisions, HolderDipsIntoTheStock) {
  const Scene s = test::box_scene({0, 0, 0}, {50, 50, 30}, short_tool());
  // Line 3 plunges the tip to z = 5: the holder face (tip + 20) is 5 mm below the top.
  const VerifyResult r = run(s, test::Moves().rapid({25, 25, 60}).line({.z = 40}, 500).line({.z = 5}).line({.z = 40}));
  ASSERT_FALSE(r.report.collisions.empty());
  bool holder = false;
  // The crash destroys the material the holder met, so the retract (block 4) is clean.
  for (const Collision& c : r.report.collisions) {
    EXPECT_EQ(c.block, 3);
    EXPECT_EQ(c.line, 3);
    EXPECT_FALSE(c.rapid);
    EXPECT_EQ(c.with, HitWith::Stock);
    EXPECT_NE(c.component, ToolComponent::Ball);  // the cutting end is no collision in a feed move
    if (c.component == ToolComponent::Holder) {
      holder = true;
      EXPECT_NEAR(c.depth_mm, 5.0, 0.25);
    }
  }
  EXPECT_TRUE(holder);
  EXPECT_TRUE(r.report.per_block[2].collision);
  EXPECT_FALSE(r.report.per_block[3].collision);
}

// With an engagement hook the cut defers its changes where the hook reads until it has returned; a holder
// crashing beside the cut (the crash removes from the material the cut left, both deferred) must leave
// the same stock and collisions as without the hook.
TEST(Collisions, TheSameWhenTheCutDefersItsChanges) {
  const Scene s = test::box_scene({0, 0, 0}, {50, 50, 30}, short_tool());
  const test::Moves m =
      test::Moves().rapid({10, 25, 60}).line({.z = 40}, 500).line({.z = 6}).line({.x = 30}).line({.y = 35}).line({.z = 40});
  const VerifyResult plain = run(s, m);
  VerifyOptions o;
  int calls = 0;
  o.engagement = [&](const Tool&, const TriDexel&, const ToolPose&, const ToolPose&, const Eigen::AlignedBox3d&) {
    ++calls;
    return Engagement{};
  };
  const VerifyResult hooked = run(s, m, o);
  EXPECT_GE(calls, 3);
  ASSERT_EQ(plain.report.collisions.size(), hooked.report.collisions.size());
  for (size_t k = 0; k < plain.report.collisions.size(); ++k) {
    const Collision &a = plain.report.collisions[k], &b = hooked.report.collisions[k];
    EXPECT_EQ(a.block, b.block);
    EXPECT_EQ(a.component, b.component);
    EXPECT_EQ(a.depth_mm, b.depth_mm);
  }
  bool holder_moving = false;  // a holder crash in the sideways feed, where the cut and the crash meet a ray
  for (const Collision& c : plain.report.collisions) holder_moving |= c.block == 4 && c.component == ToolComponent::Holder;
  EXPECT_TRUE(holder_moving);
  EXPECT_EQ(plain.report.removed_volume_mm3, hooked.report.removed_volume_mm3);
  const Lattice& L = plain.stock.lattice();
  for (int d = 0; d < 3; ++d)
    for (int iv = 0; iv < L.n[Lattice::v_axis(d)]; ++iv)
      for (int iu = 0; iu < L.n[Lattice::u_axis(d)]; ++iu) {
        const Dexel &a = plain.stock.ray(d, iu, iv), &b = hooked.stock.ray(d, iu, iv);
        ASSERT_EQ(a.size(), b.size()) << d << " " << iu << " " << iv;
        for (uint32_t k = 0; k < a.size(); ++k) {
          ASSERT_EQ(a.begin()[k].lo, b.begin()[k].lo);
          ASSERT_EQ(a.begin()[k].hi, b.begin()[k].hi);
        }
      }
}

// Ball R 3, flutes to 12, shank R 3 to the gauge length 60, no holder.
Tool long_tool() { return test::ball_tool(3, 12, 3, 60, {}); }

// A feed up the tool's axis beside an overhang (a plate z 20 to 25, the tool 2 mm under its edge, from
// below it): the shank meets the plate first, and the flutes, arriving later in the same block, cut all of
// what it met.
// The shank crashed before the flutes got there: a collision, about 2 mm deep (the overlap across the
// plate's edge).
TEST(Collisions, ShankLeadingTheFlutesIntoAnOverhang) {
  const Scene s = test::box_scene({10, 0, 20}, {30, 20, 25}, long_tool());
  const VerifyResult r = run(s, test::Moves().rapid({9, 10, -70}).line({.z = 20}, 500));
  ASSERT_EQ(r.report.collisions.size(), 1u);
  const Collision& c = r.report.collisions.front();
  EXPECT_EQ(c.block, 2);
  EXPECT_FALSE(c.rapid);
  EXPECT_EQ(c.with, HitWith::Stock);
  EXPECT_EQ(c.component, ToolComponent::Shank);
  EXPECT_NEAR(c.depth_mm, 2.0, 0.25);
  EXPECT_GT(r.report.removed_volume_mm3, 0.0);  // the flutes did cut the plate's edge
}

// The same feed the other way, down into the stock: the shank follows the flutes into the hole they cut
// (as wide as the shank), so it meets nothing, however deep the plunge.
TEST(Collisions, ShankFollowingTheFlutesMeetsNothing) {
  const Scene s = test::box_scene({0, 0, 0}, {50, 50, 30}, long_tool());
  const VerifyResult r = run(s, test::Moves().rapid({25, 25, 40}).line({.z = 2}, 500).line({.z = 40}));
  EXPECT_TRUE(r.report.collisions.empty());
  const double hole = std::numbers::pi * 9 * 25 + 2.0 / 3.0 * std::numbers::pi * 27;  // to the ball centre z = 5
  EXPECT_NEAR(r.report.removed_volume_mm3, hole, 0.01 * hole);
}

TEST(Collisions, RapidThroughTheStock) {
  const Scene s = test::box_scene({0, 0, 0}, {50, 50, 30}, short_tool());
  const VerifyResult r = run(s, test::Moves().rapid({-10, 25, 60}).rapid({.z = 25}).rapid({.x = 60}).rapid({.z = 60}));
  ASSERT_FALSE(r.report.collisions.empty());
  for (const Collision& c : r.report.collisions) {
    EXPECT_EQ(c.block, 3);
    EXPECT_EQ(c.line, 3);
    EXPECT_TRUE(c.rapid);
    EXPECT_EQ(c.with, HitWith::Stock);
  }
  EXPECT_EQ(r.report.collisions.front().component, ToolComponent::Ball);
  EXPECT_NEAR(r.report.collisions.front().depth_mm, 5.0, 0.25);  // ball 5 mm into the top... across
}

TEST(Collisions, ToolTouchesAFixture) {
  Scene s = test::box_scene({0, 0, 0}, {50, 50, 30}, short_tool());
  s.fixtures.push_back(test::box_mesh({55, 0, 0}, {70, 50, 20}));  // a clamp beside the stock
  const VerifyResult r = run(s, test::Moves().rapid({60, 25, 50}).line({.z = 25}, 500).line({.z = 18}).line({.z = 50}));
  ASSERT_FALSE(r.report.collisions.empty());
  EXPECT_EQ(r.report.collisions.front().block, 3);
  for (const Collision& c : r.report.collisions) {
    // The plunge into the clamp (line 3) and the retract out of it (line 4).
    EXPECT_EQ(c.line, c.block);
    EXPECT_TRUE(c.block == 3 || c.block == 4);
    EXPECT_EQ(c.with, HitWith::Fixture);
    EXPECT_EQ(c.component, ToolComponent::Ball);
    EXPECT_NEAR(c.depth_mm, 2.0, 0.25);
  }
  VerifyOptions o;
  o.stop_at_first_collision = true;
  const VerifyResult stopped = run(s, test::Moves().rapid({60, 25, 50}).line({.z = 25}, 500).line({.z = 18}).line({.z = 50}).line({.z = 18}), o);
  EXPECT_EQ(stopped.report.blocks, 3);
  EXPECT_TRUE(stopped.report.stopped_early);
}

TEST(Collisions, CleanProgramReportsNone) {
  Scene s = test::box_scene({0, 0, 0}, {50, 50, 30}, short_tool());
  s.fixtures.push_back(test::box_mesh({55, 0, 0}, {70, 50, 20}));
  s.check_surfaces.push_back(test::box_mesh({0, 60, 0}, {50, 70, 40}));
  s.design = test::box_mesh({-1, -1, -1}, {51, 51, 27});  // the finished top at z = 27
  const VerifyResult r = run(s, test::Moves()
                                        .rapid({-5, 10, 40})
                                        .line({.z = 27}, 800)
                                        .line({.x = 55})
                                        .line({.y = 20})
                                        .line({.x = -5})
                                        .rapid({.z = 40}));
  EXPECT_TRUE(r.report.collisions.empty());
  EXPECT_TRUE(r.report.gouges.empty());
  EXPECT_LT(r.report.max_gouge_mm, 0.01);
  EXPECT_GT(r.report.removed_volume_mm3, 0);
  EXPECT_GT(r.report.excess.samples, 0u);
  EXPECT_GT(r.report.excess.max_mm, 2.9);  // most of the top is still uncut (3 mm above the design)
}

TEST(Collisions, GougeAgainstTheDesign) {
  Scene s = test::box_scene({0, 0, 0}, {50, 50, 30}, short_tool());
  s.design = test::box_mesh({-1, -1, -1}, {51, 51, 27});
  const VerifyResult r = run(s, test::Moves()
                                        .rapid({10, 25, 40})
                                        .line({.z = 27}, 800)
                                        .line({.x = 20})
                                        .line({.z = 26.5})
                                        .line({.x = 30})
                                        .rapid({.z = 40}));
  ASSERT_EQ(r.report.gouges.size(), 2u);  // the plunge to 26.5 and the move at 26.5
  EXPECT_EQ(r.report.gouges[0].line, 4);
  EXPECT_EQ(r.report.gouges[1].line, 5);
  EXPECT_NEAR(r.report.max_gouge_mm, 0.5, 0.02);
}

// A ball turned about its centre (TCP, the tip following) over a plane it touches cuts nothing below it,
// but its swept parts may reach below by up to the sweep's bound: at --tolerance 0.05 they did by 0.02 mm,
// which was listed as a gouge. Gouges are listed beyond the block's bound.
TEST(Collisions, NoGougeWithinTheSweepsBound) {
  Scene s = test::box_scene({15, 15, 20}, {35, 35, 30}, short_tool());
  s.design = test::box_mesh({14, 14, 19}, {36, 36, 27});
  const ForwardFn fwd = [](const Joints& j) {  // A tilts the axis about x: (0, -sin A, cos A)
    const double a = j.a * std::numbers::pi / 180.0;
    return ToolPose{Eigen::Vector3d(j.x, j.y, j.z), Eigen::Vector3d(0, -std::sin(a), std::cos(a))};
  };
  test::Moves m;  // the centre stays at (25, 25, 30), 3 above the design
  m.tcp().rapid({25, 25, 40, 0}).line({.z = 27}, 300).inverse_time({.y = 28, .z = 30, .a = 90}, 10);
  VerifyOptions o;
  o.resolution = 0.05;
  o.sweep.tolerance = 0.05;
  const VerifyResult r = verify_program(s, m.program(), fwd, o);
  EXPECT_TRUE(r.report.gouges.empty());
  EXPECT_GT(r.report.max_gouge_mm, 0.01);  // what the swept parts reached: within their bound
  EXPECT_LE(r.report.max_gouge_mm, r.report.sweep_error_mm);
  bool warned = false;  // and the report says a smaller tolerance would tell
  for (const std::string& w : r.report.warnings) warned |= w.find("not listed as gouges") != std::string::npos;
  EXPECT_TRUE(warned);
  // The same turn about the tip gouges: the ball's lowest point goes 3 (1 - cos 60 deg) below the tip.
  test::Moves deep;
  deep.tcp().rapid({25, 25, 40, 0}).line({.z = 27}, 300).inverse_time({.a = 60}, 10);
  const VerifyResult g = verify_program(s, deep.program(), fwd, o);
  ASSERT_EQ(g.report.gouges.size(), 1u);
  EXPECT_NEAR(g.report.max_gouge_mm, 3.0 * (1.0 - std::cos(std::numbers::pi / 3.0)), 0.06);
}

}  // namespace
}  // namespace tf
