// Exactness of the trajectory: every output element, sampled densely, lies at the gap's distance from
// the profile (>= for sharp-corner extensions), and contours are closed and free of self-crossings.
#include "offset_test_util.hpp"
#include "tiltfield/core/error.hpp"

namespace tf::offset::test {
namespace {

struct Case {
  std::string name;
  Profile profile;
};

std::vector<Case> cases() {
  return {{"rounded_rect", scene_profile("rounded_rect.txt")},
          {"die_section", scene_profile("die_section.txt")},
          {"two_lobes_neck", scene_profile("two_lobes_neck.txt")},
          {"lobes_wide_neck", profile_text(lobes_text(20, 8, 25))},
          {"turbine_blade", scene_profile("blade_section.txt")}};
}

TEST(OffsetExact, ConstantGapEveryElementAtTheGap) {
  for (const auto& c : cases())
    for (Side side : {Side::Inside, Side::Outside})
      for (Corner corner : {Corner::Round, Corner::Sharp})
        for (double gap : {0.5, 3.0, 7.0}) {
          OffsetOptions o;
          o.side = side;
          o.corner = corner;
          const auto r = offset_profile(c.profile, constant_gap(gap), o);
          SCOPED_TRACE(c.name + (side == Side::Inside ? " inside" : " outside") +
                       (corner == Corner::Round ? " round" : " sharp") + " gap " + std::to_string(gap));
          if (side == Side::Outside) {
            ASSERT_GE(r.contours.size(), 1u);
          }
          const auto e = check_exactness(c.profile, constant_gap(gap), r);
          EXPECT_LE(e.max_error, 1e-6);
          EXPECT_GE(e.min_sharp, -1e-6);
          expect_clean_contours(r);
          if (corner == Corner::Round) {
            for (const auto& ct : r.contours)
              for (const auto& s : ct) EXPECT_NE(s.kind, SegmentKind::SharpJoin);
          }
        }
}

TEST(OffsetExact, NeckSplitsIntoTwoContours) {
  const Profile p = scene_profile("two_lobes_neck.txt");  // neck half-width 5
  EXPECT_EQ(offset_profile(p, constant_gap(4.0), {}).contours.size(), 1u);
  EXPECT_EQ(offset_profile(p, constant_gap(6.0), {}).contours.size(), 2u);
  EXPECT_EQ(offset_profile(p, constant_gap(31.0), {}).contours.size(), 0u);  // wider than the lobes
}

// A neck exactly twice the gap wide narrows the region to zero width: the two pockets come out as two
// contours, as a micrometre wider a gap gives, with no piece run out along the neck and back (the contour
// had retraced the neck; in square lobes it ran there and back round the far pocket; found by black-box
// testing).
TEST(OffsetExact, NeckExactlyTwiceTheGapSplitsWithoutABridge) {
  const std::string square_lobes =
      "START -15 -10\n0 10 0\n0 0 5\n0 10 0\n0 0 -5\n0 10 0\n0 0 20\n0 -10 0\n0 0 -5\n0 -10 0\n0 0 5\n0 -10 0\n0 0 -20\n";
  for (const auto& [name, profile] : {std::pair{"two_lobes_neck", scene_profile("two_lobes_neck.txt")},
                                      std::pair{"square_lobes", profile_text(square_lobes)}})
    for (Corner corner : {Corner::Round, Corner::Sharp}) {
      SCOPED_TRACE(std::string(name) + (corner == Corner::Round ? " round" : " sharp"));
      OffsetOptions o;
      o.corner = corner;
      const auto r = offset_profile(profile, constant_gap(5.0), o);
      const auto wider = offset_profile(profile, constant_gap(5.0 + 1e-6), o);
      ASSERT_EQ(r.contours.size(), 2u);
      EXPECT_EQ(wider.contours.size(), 2u);
      EXPECT_NEAR(total_area(r), total_area(wider), 1e-3);
      expect_clean_contours(r);
      std::vector<Eigen::Vector2d> mids;
      for (const auto& c : r.contours)
        for (const auto& seg : c) mids.push_back(point_at(seg, 0.5));
      for (size_t i = 0; i < mids.size(); ++i)
        for (size_t j = i + 1; j < mids.size(); ++j) EXPECT_GT((mids[i] - mids[j]).norm(), 1e-6) << "a piece run twice";
    }
}

TEST(OffsetExact, VariableGapFollowsTheLaw) {
  for (const auto& c : cases()) {
    const double L = chain_length(c.profile.elements);
    GapLaw law;
    law.s = {0, 0.3 * L, 0.55 * L, L};
    law.gap = {1.0, 2.5, 1.5, 1.0};
    for (double blend : {0.0, 2.0})
      for (Side side : {Side::Inside, Side::Outside}) {
        law.blend = blend;
        SCOPED_TRACE(c.name + " blend " + std::to_string(blend) + (side == Side::Inside ? " inside" : " outside"));
        OffsetOptions o;
        o.side = side;
        const auto r = offset_profile(c.profile, law, o);
        ASSERT_GE(r.contours.size(), 1u);
        const auto e = check_exactness(c.profile, law, r);
        EXPECT_LE(e.max_error, 1e-6);
        EXPECT_LE(e.max_fitted, 1e-6);
        EXPECT_GE(e.min_sharp, -1e-6);
        // Across a junction the law jumps between the two closest points' values; the transition stays
        // within that jump (here at most 2.5 - 1.0 mm).
        EXPECT_GE(e.min_transition, -1.5 - 1e-6);
        // Transitions are short stretches at junctions, not the bulk of the path.
        double total = 0;
        for (const auto& ct : r.contours) total += chain_length(ct);
        EXPECT_LE(e.transition_length, 0.05 * total);
        expect_clean_contours(r);
      }
  }
}

// A law rising steeply into a vertex tilts the incoming offset into the outgoing one's gap without meeting
// it: an arc about the vertex had closed the chain, a fold that loop removal left (the contour 0.46 mm
// inside the law's gap before an arc), or the whole offset was dropped as "empty" (before a line). The
// outgoing offset continued back meets an earlier one (black-box testing). And a law knot written to 9
// decimals 2e-10 mm inside an octagon's side left a sliver of a piece with nothing to join ("empty").
TEST(OffsetExact, ALawRisingOrFallingSteeplyAtAVertexKeepsEveryGap) {
  struct Case {
    const char* name;
    std::string profile;
    GapLaw law;
    Side side = Side::Inside;
  };
  GapLaw into_line, into_arc, octagon;
  into_line.s = {0, 9, 10, 30, 40, 56};
  into_line.gap = {0.5, 0.5, 1, 1, 0.5, 0.5};
  into_arc.s = {0, 20, 30, 55.157305176, 56.157305176};
  into_arc.gap = {1, 1, 0.2, 0.2, 1};
  std::string octagon_text = "START 8 0\n";
  for (int i = 0; i < 8; ++i) {
    const double a0 = 2 * M_PI * i / 8, a1 = 2 * M_PI * (i + 1) / 8;
    octagon_text += "0 " + std::to_string(8 * (std::cos(a1) - std::cos(a0))) + " " +
                    std::to_string(8 * (std::sin(a1) - std::sin(a0))) + "\n";
  }
  const double side = 16 * std::sin(M_PI / 8);
  octagon.s = {0, side - 1, std::round(side * 1e9) / 1e9, 2 * side, 3 * side, 8 * side};
  octagon.gap = {0.5, 0.5, 1, 1, 0.5, 0.5};
  // Falling steeply out of a square's corner (found "empty"), and a peak at the corner rising and falling
  // along one line (a 0.42 mm2 loop in the corner had been the whole result).
  const GapLaw out_of{{0, 10, 11, 20, 30, 40}, {1.2, 1.2, 0.3, 0.3, 1.2, 1.2}, 0.0, ""};
  const GapLaw peak{{0, 9, 10, 11, 40}, {0.5, 0.5, 1.5, 0.5, 0.5}, 0.0, ""};
  const std::string square = "START 0 0\n0 10 0\n0 0 10\n0 -10 0\n0 0 -10\n";
  // A law's peak at an arc-arc vertex of a thin region (inside), and a rise and steep fall beside a
  // line-line vertex (outside): the valid slices made a sliver of three beside the contour, whose turn the
  // stitching took and left the contour open, "empty" (black-box testing).
  const GapLaw thin_peak{{0, 18.57, 27.1, 35.06289646}, {1.3, 1.3, 2.2, 1.3}, 0.0, ""};
  const GapLaw rise_fall{{0, 17.051, 31.566, 38.829056881}, {1, 2, 0.8, 1}, 0.0, ""};
  const std::string thin = "START -4.117 -0.514\n-9.33 -1.952 -2.446\n0 14.476 -5.360\n19.687 -4.692 7.029\n14.914 -7.832 0.777\n";
  const std::string mixed = "START 9.964 2.325\n27.73 -17.153 -0.540\n-1.477 1.174 -2.258\n0 0.625 -0.784\n"
                            "4.949 1.386 -1.434\n0 7.868 0.844\n0 6.100 4.172\n";
  const std::vector<Case> cases = {
      {"thin region, peak at a vertex", thin, thin_peak, Side::Inside},
      {"outside, rise and fall", mixed, rise_fall, Side::Outside},
      {"into a line", "START 0 0\n0 10 0\n0 4 3\n0 0 12\n0 -14 0\n0 0 -15\n", into_line},
      {"out of a corner", square, out_of},
      {"peak at a corner", square, peak},
      {"into an arc", "START 10 0\n-6 4 3\n0 0 12\n0 -14 0\n0 0 -15\n0 10 0\n", into_arc},
      {"octagon", octagon_text, octagon}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Profile p = profile_text(c.profile);
    GapLaw law = c.law;
    law.s.back() = chain_length(p.elements);  // closes exactly on the profile
    OffsetOptions options;
    options.side = c.side;
    const auto r = offset_profile(p, law, options);
    EXPECT_EQ(r.contours.size(), 1u);
    if (r.contours.size() != 1) continue;
    const auto e = check_exactness(p, law, r, 256);
    EXPECT_LE(e.max_error, 1e-6);
    EXPECT_LE(e.max_fitted, 1e-6);
    EXPECT_GE(e.min_transition, -1e-6);  // never closer than the law
    expect_clean_contours(r);
  }
}

// Where a law differs much across a change of the closest element (a valley of the law facing the other
// side of a thin region; a rise past an arc that vanishes), pieces of the raw offset run from closer than
// the law to farther without a crossing: the boundary runs along the medial axis, which is not built. They
// are counted, with a point, so that `offset` says so instead of "empty" (black-box testing); what is kept
// is never closer than the law.
TEST(OffsetExact, ALawWhoseBoundaryLeavesTheOffsetsIsNamed) {
  struct Case {
    const char* name;
    std::string profile;
    GapLaw law;
    Side side;
  };
  const std::vector<Case> cases = {
      {"valley facing a thin side",
       "START 9.815 8.950\n7.923 -6.505 -1.652\n0 -9.963 -1.160\n0 2.442 -3.703\n-9.672 -7.780 -3.578\n0 8.507 -1.531\n"
       "17.835 -2.434 -8.293\n0 3.005 3.315\n-15.872 8.277 4.694\n-5.706 -0.026 -3.350\n-17.301 5.880 -1.075\n"
       "13.336 -1.707 5.280\n0 0.304 11.053\n",
       {{0, 44.575, 52.115005363, 76.776656748, 85.093, 87.833836542}, {4.328, 4.532, 5.052, 4.864, 1.179, 4.328}, 0.0, ""},
       Side::Inside},
      {"rise past a vanishing arc",
       "START 3.980 0.198\n-7.101 3.003 0.357\n0 1.385 0.271\n0 1.164 2.419\n0 -5.717 1.090\n9.826 -7.213 6.217\n"
       "-15.914 -0.240 -5.365\n13.476 -5.384 -1.881\n0 5.708 -9.519\n-1.419 1.124 -0.115\n0 3.912 1.059\n"
       "0 2.380 2.072\n-5.622 -0.122 3.395\n",
       {{0, 22.948, 24.125, 45.101, 56.967838506}, {3.752, 9.993, 7.613, 2.035, 3.752}, 0.0, ""},
       Side::Outside}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Profile p = profile_text(c.profile);
    GapLaw law = c.law;
    law.s.back() = chain_length(p.elements);
    OffsetOptions options;
    options.side = c.side;
    const auto r = offset_profile(p, law, options);
    EXPECT_GT(r.unresolved, 0);
    const auto field = make_clearance_field(p, law);
    EXPECT_GT(clearance(*field, r.unresolved_at), 0.0);  // the point lies farther than the law
    if (r.contours.empty()) continue;
    const auto e = check_exactness(p, law, r, 128);
    EXPECT_LE(e.max_error, 1e-6);
    EXPECT_GE(e.min_transition, -1e-6);
  }
  // A constant gap's pieces are never counted.
  const auto r = offset_profile(scene_profile("rounded_rect.txt"), constant_gap(2), {});
  EXPECT_EQ(r.unresolved, 0);
}

TEST(OffsetExact, GapLawMustCloseOnClosedProfile) {
  const Profile p = scene_profile("rounded_rect.txt");
  GapLaw law;
  law.s = {0, 100};
  law.gap = {1, 2};
  law.file = "law.csv";
  EXPECT_THROW(offset_profile(p, law, {}), InputError);
  // Within the closure's snap (1e-6 mm) the gaps are equal: a law ending at s = 302.832 on the profile
  // 302.8318531 long (black-box testing: refused for 4.8e-7 mm, "1 differs from 1").
  law.s = {0, 150, 302.832};
  law.gap = {1, 1.5, 1};
  const OffsetResult r = offset_profile(p, law, {});
  EXPECT_EQ(r.contours.size(), 1u);
  expect_clean_contours(r);
  law.s = {0, 150, 302.9};
  try {
    offset_profile(p, law, {});
    ADD_FAILURE() << "a gap 2.3e-4 mm off at the end accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("by 0.000223 mm"), std::string::npos) << e.what();
  }
}

TEST(OffsetExact, GapLawInterpolatesLinearlyAndBlends) {
  GapLaw law;
  law.s = {0, 10, 20};
  law.gap = {1, 2, 1};
  EXPECT_DOUBLE_EQ(gap_at(law, -5), 1);
  EXPECT_DOUBLE_EQ(gap_at(law, 5), 1.5);
  EXPECT_DOUBLE_EQ(gap_at(law, 10), 2);
  EXPECT_DOUBLE_EQ(gap_at(law, 25), 1);
  law.blend = 2;
  EXPECT_DOUBLE_EQ(gap_at(law, 5), 1.5);                 // outside the blend windows
  EXPECT_NEAR(gap_at(law, 10), 2 - 0.1 * 2 / 2, 1e-12);  // parabola apex: g_k + (m2 - m1) w / 4
  const double h = 1e-6;                                 // C1 at the window ends
  for (double s : {8.0, 12.0})
    EXPECT_NEAR((gap_at(law, s + h) - gap_at(law, s)) / h, (gap_at(law, s) - gap_at(law, s - h)) / h, 1e-5);
}

}  // namespace
}  // namespace tf::offset::test
