// A section's contours cleaned without letting them cross: the cases that left the end mill's surface open
// at --step 0.15 and 0.1 (a hole sharing an edge with its outer contour; a hole pushed across its outer
// contour by cleaning), on hand-made contours in Clipper units (nm).
#include <gtest/gtest.h>

#include "section_contours.hpp"

namespace tf::grind::detail {
namespace {

using ClipperLib::Path;
using ClipperLib::Paths;

constexpr double kClean = 500;  // nm, the default cleaning distance

double signed_area(const Paths& paths) {
  double a = 0;
  for (const Path& p : paths) a += ClipperLib::Area(p);
  return a;
}

TEST(SectionContours, EdgesCrossCountsCrossingsAndOverlapsNotTouches) {
  const Path square{{0, 0}, {1000, 0}, {1000, 1000}, {0, 1000}};
  EXPECT_FALSE(edges_cross({square}));
  EXPECT_TRUE(edges_cross({square, Path{{500, 500}, {1500, 500}, {1500, 600}}}));           // crosses an edge
  EXPECT_FALSE(edges_cross({square, Path{{1000, 0}, {2000, 0}, {2000, -500}}}));          // in line, end to end
  EXPECT_FALSE(edges_cross({square, Path{{1000, 1000}, {2000, 1000}, {2000, 2000}}}));    // touches at a corner
  EXPECT_FALSE(edges_cross({square, Path{{1000, 500}, {2000, 0}, {2000, 1000}}}));        // a corner on an edge
  EXPECT_TRUE(edges_cross({square, Path{{200, 0}, {600, 0}, {400, 300}}}));               // overlaps along 0.4 um
  EXPECT_TRUE(edges_cross({Path{{0, 0}, {1000, 1000}, {1000, 0}, {0, 1000}}}));           // a bow tie
}

// Clipper's strictly simple output held a hole whose edge is its outer contour's edge run the other way: the
// region is a notch in the outer contour, and the shared edge bounds nothing.
TEST(SectionContours, AHoleSharingAnEdgeWithItsOuterContourBecomesANotch) {
  const Path outer{{0, 0}, {300000, 0}, {600000, 0}, {1000000, 0}, {1000000, 1000000}, {0, 1000000}};
  const Path hole{{600000, 0}, {300000, 0}, {450000, 200000}};
  ASSERT_LT(ClipperLib::Area(hole), 0);
  ASSERT_TRUE(edges_cross({outer, hole}));
  const Paths out = tidy_contours({outer, hole}, kClean);
  EXPECT_FALSE(edges_cross(out));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(signed_area(out), ClipperLib::Area(outer) + ClipperLib::Area(hole));
}

// The outer contour dips 300 nm below the line of its neighbours, which cleaning straightens; a hole's
// corner 100 nm below that line would then lie outside the outer contour. The section keeps its dip.
TEST(SectionContours, CleaningThatWouldPushAHoleAcrossItsOuterContourIsLeftOut) {
  const Path outer{{0, 0}, {500000, -300}, {1000000, 0}, {1000000, 1000000}, {0, 1000000}};
  const Path hole{{500000, -100}, {400000, 200000}, {600000, 200000}};
  ASSERT_LT(ClipperLib::Area(hole), 0);
  ASSERT_FALSE(edges_cross({outer, hole}));
  Paths plain;
  ClipperLib::CleanPolygons(Paths{outer, hole}, plain, kClean);
  ASSERT_TRUE(edges_cross(plain));  // what cleaning alone makes of it
  const Paths out = tidy_contours({outer, hole}, kClean);
  EXPECT_FALSE(edges_cross(out));
  EXPECT_DOUBLE_EQ(signed_area(out), ClipperLib::Area(outer) + ClipperLib::Area(hole));
}

// A sliver 0.2 um wide on average (the end mill's 3-point holes: 0.4 um) is below the cleaning distance and goes; a cleaned
// section that crosses nothing is what cleaning makes of it.
TEST(SectionContours, SliversNarrowerThanTheCleaningDistanceGo) {
  const Path outer{{0, 0}, {1000000, 0}, {1000000, 1000000}, {0, 1000000}};
  const Path sliver{{100000, 500000}, {100000, 500400}, {190000, 500800}};  // 90 um long, 0.2 um on average
  const Path wide{{300000, 300000}, {300000, 400000}, {400000, 400000}};     // a hole 100 um across
  const Paths out = tidy_contours({outer, sliver, wide}, kClean);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_DOUBLE_EQ(signed_area(out), ClipperLib::Area(outer) + ClipperLib::Area(wide));
}

}  // namespace
}  // namespace tf::grind::detail
