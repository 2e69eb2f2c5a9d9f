// Against Clipper (polygonised at 0.001 mm) as an independent reference: enclosed areas agree within
// 0.01 % and the number of contours agrees, including the two-lobes-and-a-neck shape that splits.
#include "offset_test_util.hpp"

namespace tf::offset::test {
namespace {

void compare(const Profile& p, double gap, Side side, const std::string& what, int expect_contours = -1) {
  SCOPED_TRACE(what + (side == Side::Inside ? " inside" : " outside") + " gap " + std::to_string(gap));
  OffsetOptions o;
  o.side = side;
  const auto ours = offset_profile(p, constant_gap(gap), o);
  const auto ref = clipper_offset(p, gap, side);
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

}  // namespace
}  // namespace tf::offset::test
