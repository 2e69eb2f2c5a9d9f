// Wheels given by a profile of a few points (a V, a double cone), against closed forms of what they grind,
// and the cleaning of finely sampled section contours (black-box testing: a V-wheel plunge ground nothing,
// a double cone only every fifth section).
#include <gtest/gtest.h>

#include <cmath>
#include <polyclipping/clipper.hpp>

#include "grind_test_util.hpp"
#include "section_contours.hpp"
#include "tiltfield/grind/sections.hpp"

namespace tf::grind {
namespace {

constexpr double kBlankR = 5.0;

GrindScene profile_scene(double length, const std::vector<Eigen::Vector2d>& profile, const std::string& program,
                         const Axes& start) {
  GrindScene s = testing::make_scene(kBlankR, length, 40.0, 4.0, 0.0, program, start);
  s.wheel.profile = profile;
  return s;
}

// The area of the blank circle on the side y >= lower(x) of a curve, by the midpoint rule over x.
template <class Lower>
double circle_above(Lower lower, int n = 200000) {
  double area = 0.0;
  const double h = 2.0 * kBlankR / n;
  for (int i = 0; i < n; ++i) {
    const double x = -kBlankR + (i + 0.5) * h, top = std::sqrt(kBlankR * kBlankR - x * x);
    const double lo = lower(x);
    if (std::isfinite(lo)) area += std::max(0.0, top - std::max(lo, -top)) * h;
  }
  return area;
}

// A V-wheel (rho 30 at the faces, 40 at its middle: three points) plunged radially from y = 80 to 20 with
// its axis along x, 32 mm below the blank's base. In the plane z the section of the wheel at y = Y is
// (y - Y)^2 + (z + 32)^2 <= rho(x)^2, so the plunge removes y >= 20 - sqrt(rho(x)^2 - (z + 32)^2): only the
// wheel's flanks reach the blank, between the profile's points.
TEST(WheelProfile, AVWheelPlungedRadiallyGrindsWhatItsFlanksReach) {
  const GrindScene scene = profile_scene(10.0, {{-2, 30}, {0, 40}, {2, 30}}, "OP gashing v\nG1 Y20\nG0 Y80\n",
                                         {0, 80, -32, 0, 0, 0});
  SectionOptions opt;
  opt.spacing = 0.1;
  const SectionStack stack = simulate_sections(scene, opt);
  const double blank = section_area(stack.sections.back());  // z = 10: beyond the wheel's reach
  double removed = 0.0, removed_exact = 0.0;
  for (size_t i = 0; i < stack.sections.size(); ++i) {
    const double z = stack.sections[i].z, d = z + 32.0;
    const double exact = circle_above([d](double x) {
      const double rho = 40.0 - 5.0 * std::abs(x);
      return std::abs(x) <= 2.0 && rho >= d ? 20.0 - std::sqrt(rho * rho - d * d) : INFINITY;
    });
    const double got = blank - section_area(stack.sections[i]);
    EXPECT_NEAR(got, exact, 0.01 + 0.003 * exact) << "z = " << z;
    const double w = (i == 0 || i + 1 == stack.sections.size()) ? 0.5 : 1.0;
    removed += w * got * opt.spacing;
    removed_exact += w * exact * opt.spacing;
  }
  EXPECT_GT(removed_exact, 15.0);
  EXPECT_NEAR(removed, removed_exact, 0.003 * removed_exact);
}

// A double cone (rho 0 at the faces, 40 in the middle) run along the blank at 38 mm from its axis: every
// section loses y >= -2 + 20 |x|, whether or not it lies where an increment ends.
TEST(WheelProfile, ADoubleConeFluteCutsEverySection) {
  const GrindScene scene = profile_scene(3.0, {{-2, 0}, {0, 40}, {2, 0}},
                                         "OP fluting v\nG0 Z-60\nG0 X0 Y38\nG1 Z70\nG0 Y80\n", {0, 80, 0, 0, 0, 0});
  SectionOptions opt;
  opt.spacing = 0.05;
  const SectionStack stack = simulate_sections(scene, opt);
  const double removed = circle_above([](double x) { return -2.0 + 20.0 * std::abs(x); });
  const double exact_circle = M_PI * kBlankR * kBlankR;
  for (const Section& s : stack.sections) {
    const double area = section_area(s);
    // The blank polygon's chords (0.002 mm) take at most 0.04 mm2 off the circle.
    EXPECT_NEAR(area, exact_circle - removed, 0.06) << "z = " << s.z;
    EXPECT_LT(area, exact_circle - removed + 0.01) << "z = " << s.z;
  }
}

// The nearest point of a section's contours to the blank axis (mm).
double nearest_to_axis(const Section& s) {
  double r = INFINITY;
  for (const Contour& c : s.contours)
    for (size_t i = 0; i < c.points.size(); ++i) {
      const Eigen::Vector2d a = c.points[i], b = c.points[(i + 1) % c.points.size()], d = b - a;
      const double t = std::clamp(-a.dot(d) / std::max(d.squaredNorm(), 1e-30), 0.0, 1.0);
      r = std::min(r, (a + t * d).norm());
    }
  return r;
}

const Section& section_at(const SectionStack& stack, double z) {
  const Section* best = &stack.sections.front();
  for (const Section& s : stack.sections)
    if (std::abs(s.z - z) < std::abs(best->z - z)) best = &s;
  return *best;
}

// A flat rim given as a profile of its two ends, swivelled 30 degrees and plunged to 32 mm from the blank
// axis: the plane z = 5 through the wheel's centre meets it in an ellipse's arc, which the two end rings
// took as its chord (0.13 mm shallow, black-box testing). The section is ground to radius 2.
TEST(WheelProfile, AFlatRimGivenByItsEndsGrindsToDepthWhenSwivelled) {
  GrindScene scene = profile_scene(10.0, {{-5, 30}, {5, 30}}, "OP gashing flat\nG1 Y32\nG0 Y50\n",
                                   {2.5, 50, 4.330127, 0, 0, 30});
  scene.wheel.radius = 30.0;
  scene.wheel.thickness = 10.0;
  const SectionStack stack = simulate_sections(scene, {});
  EXPECT_NEAR(nearest_to_axis(section_at(stack, 5.0)), 2.0, 0.003);
}

// The spindle along the blank (W = 90) while the blank turns a full revolution: the generators are
// numbered from the blank's turned x, so the sweep follows them; a fixed x had left the ids in place and
// the hull of both sections cut 0.008 mm too deep at the default step (black-box testing).
TEST(WheelProfile, TurningUnderASpindleAlongTheBlankKeepsTheRadius) {
  GrindScene scene = testing::make_scene(kBlankR, 10.0, 30.0, 4.0, 0.0, "OP od_sharpening\nG1 Y32\nG1 A360\nG0 Y50\n",
                                         {5, 50, 0, 0, 0, 90});
  const SectionStack stack = simulate_sections(scene, {});
  const Section& s = section_at(stack, 5.0);
  EXPECT_NEAR(nearest_to_axis(s), 2.0, 0.002);
  // Within the chord tolerance all round: the area of a ring 2 mm across and 0.002 mm wide. Where the
  // generators' polygon meets the axis depends on how many there are (385 for this wheel: 1.2 um wide of 2.000).
  EXPECT_NEAR(section_area(s), M_PI * 4.0, 2.0 * M_PI * 2.0 * SectionOptions{}.chord_tolerance);
}

// The same under a large wheel (R 300): 180 generators' chords had left the section 0.045 mm shallow
// (R (1 - cos(pi / 180))); their number now follows the chord tolerance (black-box testing).
TEST(WheelProfile, ALargeWheelAlongTheBlankKeepsTheRadiusWithinTheChordTolerance) {
  const GrindScene scene = testing::make_scene(kBlankR, 10.0, 300.0, 4.0, 0.0,
                                               "OP od_sharpening\nG1 Y302\nG1 A360\nG0 Y320\n", {5, 320, 0, 0, 0, 90});
  const SectionStack stack = simulate_sections(scene, {});
  EXPECT_NEAR(nearest_to_axis(section_at(stack, 5.0)), 2.0, 0.003);
}

// Cleaning drops a vertex only where it stays within the cleaning distance of the edge that replaces it. On
// an arc sampled every 8 um Clipper's CleanPolygons, which tests each vertex against its current neighbours,
// ran on and left chords far off the arc.
TEST(WheelProfile, CleaningAFinelySampledArcKeepsItWithinTheDistance) {
  constexpr double kClean = 500.0, kRadius = 16e6;  // nm
  ClipperLib::Path arc;
  for (int i = 0; i <= 4000; ++i) {
    const double a = -0.5 + 1.0 * i / 4000;  // one radian, points 4 um apart
    arc.push_back({std::llround(kRadius * std::sin(a)), std::llround(kRadius * (1.0 - std::cos(a)))});
  }
  arc.push_back({0, 20000000});  // closed across the arc's chord side
  auto worst = [&](const ClipperLib::Path& cleaned) {
    double far = 0.0;
    for (const auto& q : arc) {
      double best = 1e300;
      for (size_t i = 0; i < cleaned.size(); ++i) {
        const auto &a = cleaned[i], &b = cleaned[(i + 1) % cleaned.size()];
        const Eigen::Vector2d u(double(b.X - a.X), double(b.Y - a.Y)), v(double(q.X - a.X), double(q.Y - a.Y));
        const double t = std::clamp(v.dot(u) / std::max(u.squaredNorm(), 1.0), 0.0, 1.0);
        best = std::min(best, (v - t * u).norm());
      }
      far = std::max(far, best);
    }
    return far;
  };
  ClipperLib::Path plain;
  ClipperLib::CleanPolygon(arc, plain, kClean);
  ASSERT_GT(worst(plain), 10 * kClean);  // what Clipper's cleaning makes of it
  const ClipperLib::Path cleaned = detail::clean_contour(arc, kClean);
  EXPECT_LE(worst(cleaned), kClean + 1.0);
  EXPECT_LT(cleaned.size(), arc.size() / 4);  // and it still drops most of them
}

}  // namespace
}  // namespace tf::grind
