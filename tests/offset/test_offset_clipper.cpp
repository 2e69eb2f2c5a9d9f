// Against Clipper (polygonised at 0.001 mm) as an independent reference: enclosed areas agree within
// 0.01 % and the number of contours agrees, including the two-lobes-and-a-neck shape that splits.
#include "offset_test_util.hpp"

namespace tf::offset::test {
namespace {

void compare(const Profile& p, double gap, Side side, const std::string& what, int expect_contours = -1,
             double poly_tol = 0.001) {
  SCOPED_TRACE(what + (side == Side::Inside ? " inside" : " outside") + " gap " + std::to_string(gap));
  OffsetOptions o;
  o.side = side;
  const auto ours = offset_profile(p, constant_gap(gap), o);
  const auto ref = clipper_offset(p, gap, side, false, poly_tol);
  EXPECT_EQ(static_cast<int>(ours.contours.size()), ref.contours);
  if (expect_contours >= 0) {
    EXPECT_EQ(static_cast<int>(ours.contours.size()), expect_contours);
  }
  const double a = std::abs(total_area(ours)), b = std::abs(ref.area);
  EXPECT_LE(std::abs(a - b), 1e-4 * b) << "ours " << a << " clipper " << b;
}

TEST(OffsetVsClipper, AreasAndContourCounts) {
  const Profile neck = scene_profile("two_lobes_neck.txt");
  compare(neck, 3.0, Side::Inside, "neck", 1);
  compare(neck, 6.0, Side::Inside, "neck", 2);
  compare(neck, 6.0, Side::Outside, "neck", 1);
  for (const char* f : {"rounded_rect.txt", "die_section.txt", "blade_section.txt"}) {
    const Profile p = scene_profile(f);
    for (double gap : {0.5, 2.0, 5.0})
      for (Side side : {Side::Inside, Side::Outside}) compare(p, gap, side, f);
  }
}

TEST(OffsetVsClipper, OutsideOffsetThatClosesAHole) {
  // A square with a 20 mm cavity reached by a 2 mm slot; the slot closes under an outside offset of 1.5 mm: outer contour plus a hole.
  const Profile c = profile_text(
      "START 0 0\n0 40 0\n0 0 19\n0 -10 0\n0 0 -9\n0 -20 0\n0 0 20\n0 20 0\n0 0 -9\n0 10 0\n0 0 19\n0 -40 0\n"
      "0 0 -40\n");
  compare(c, 1.5, Side::Outside, "C-shape", 2);
  compare(c, 0.5, Side::Outside, "C-shape", 1);
}

// An arc whose radius is the gap offsets to its centre point, and each neighbour joins that point about its
// own vertex. Dropped, the neighbours had been joined by one arc about the wrong vertex (radius 1 at its
// start and 2.24 at its end, a gouge of 0.27 mm on the R 2 bump) or not at all (an outside offset "empty");
// a gap 1e-7 above the radius left zero-area loops beside the contour (black-box testing).
TEST(OffsetVsClipper, ArcWhoseRadiusIsTheGap) {
  const std::string square_with = "START 0 0\n0 10 0\n0 0 10\n0 -4 0\n";
  const Profile bump = profile_text(square_with + "1 -2 0\n0 -4 0\n0 0 -10\n");
  const Profile notch = profile_text(square_with + "-1 -2 0\n0 -4 0\n0 0 -10\n");
  const Profile wide = profile_text("START 0 0\n0 20 0\n0 0 10\n0 -8.5 0\n2 -3 0\n0 -8.5 0\n0 0 -10\n");
  const Profile waves = profile_text("START 0 0\n0 20 0\n0 0 10\n2.5 -5 0\n-2.5 -5 0\n2.5 -5 0\n0 -5 0\n0 0 -10\n");
  struct Case {
    const Profile& p;
    double radius;
    Side side;
    const char* name;
  };
  for (const Case& c : {Case{bump, 1, Side::Inside, "bump"}, Case{notch, 1, Side::Outside, "notch"},
                        Case{wide, 2, Side::Inside, "wide bump"}, Case{waves, 2.5, Side::Inside, "waves"}})
    for (double gap : {c.radius - 1e-7, c.radius, c.radius + 1e-7}) {
      compare(c.p, gap, c.side, c.name, 1, 1e-5);  // 0.001 mm chords put the waves' area 2.5e-4 off
      OffsetOptions o;
      o.side = c.side;
      const OffsetResult r = offset_profile(c.p, constant_gap(gap), o);
      EXPECT_LE(check_exactness(c.p, constant_gap(gap), r).max_error, 1e-6) << c.name << " " << gap;
      for (const auto& contour : r.contours)
        for (const Segment& s : contour)
          if (s.is_arc()) {
            EXPECT_NEAR((s.a - s.c).norm(), s.r, 1e-9) << c.name << " " << gap;
            EXPECT_NEAR((s.b - s.c).norm(), s.r, 1e-9) << c.name << " " << gap;
          }
      expect_clean_contours(r);
    }
}

}  // namespace
}  // namespace tf::offset::test
