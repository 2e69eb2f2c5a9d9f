// The blank turning (A) while the wheel is in it: cylindrical grinding against its closed form. The hull of
// two turned wheel sections joins opposite corners of them and cuts a chord into the material the wheel
// leaves (0.6.14: radius 3.950 for 4.000 at the default step); the turning section's own sweep does not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "grind_test_util.hpp"
#include "tiltfield/grind/sections.hpp"

namespace tf::grind {
namespace turning_test {

constexpr double kR = 5.0, kL = 30.0, kWheelR = 40.0, kYc = 44.0, kZc = 15.0;

// The radius the blank keeps at height z: a wheel of radius 40 whose disc lies in the plane x = const (its
// axis along x, W = 0), centre at y = 44, z = 15, turned a full revolution about the blank: the nearest
// point of its section by the plane z is the middle of the section's lower edge.
double ground_radius(double z) {
  const double dz = z - kZc;
  if (std::abs(dz) >= kWheelR) return kR;
  return std::min(kR, kYc - std::sqrt(kWheelR * kWheelR - dz * dz));
}

// The smallest and largest distance of a section's contour points from the blank axis.
std::pair<double, double> radius_range(const Section& s) {
  double lo = 1e300, hi = 0.0;
  for (const Contour& c : s.contours)
    for (const Eigen::Vector2d& p : c.points) lo = std::min(lo, p.norm()), hi = std::max(hi, p.norm());
  return {lo, hi};
}

void expect_cylindrical_grinding(double thickness, double step) {
  const std::string program = "OP od_sharpening turn\nG0 X0 Y100 Z15\nG0 Y44\nG1 A360 F100\nG0 Y100\n";
  const GrindScene scene = testing::make_scene(kR, kL, kWheelR, thickness, 0.0, program);
  SectionOptions o;
  o.spacing = 0.5;
  o.step = step;
  const SectionStack stack = simulate_sections(scene, o);
  int checked = 0;
  for (const Section& s : stack.sections) {
    const double want = ground_radius(s.z);
    if (want >= kR - 0.01) continue;  // untouched there
    const auto [lo, hi] = radius_range(s);
    // The blank circle's polygon and the wheel's rings are within 0.002 mm; between two increments the
    // ground circle is left as the corner of two tangents, r (turn^2 / 8) with a turn of step / R.
    const double turn = step / kR, tol = 0.004 + want * turn * turn / 8.0;
    EXPECT_NEAR(lo, want, tol) << "z " << s.z << ", thickness " << thickness << ", step " << step;
    EXPECT_NEAR(hi, want, tol) << "z " << s.z << ", thickness " << thickness << ", step " << step;
    ++checked;
  }
  EXPECT_GE(checked, 10);
}

// The same with the workhead swivelled (W), so that the wheel's section is cut by the generator lines too:
// the radius each section keeps is the least distance from the blank's axis of the wheel's section at A = 0
// (a full revolution brings every angle round), found by scanning the wheel's solid directly.
double swivelled_ground_radius(const WheelPose& p, double R, double w, double z) {
  double best = kR;
  for (int k = 0; k < 720; ++k) {
    const double phi = 2.0 * M_PI * k / 720;
    auto inside = [&](double rho) {
      const Eigen::Vector3d d = Eigen::Vector3d(rho * std::cos(phi), rho * std::sin(phi), z) - p.centre;
      const double t = d.dot(p.axis);
      return std::abs(t) <= 0.5 * w && (d - t * p.axis).norm() <= R;
    };
    // The wheel is convex, so a ray from the axis meets it in one stretch: stepped to it, then bisected.
    for (double rho = 0.005; rho < best + 0.005; rho += 0.005) {
      if (!inside(rho)) continue;
      double out = rho - 0.005, in = rho;
      while (in - out > 1e-6) (inside(0.5 * (in + out)) ? in : out) = 0.5 * (in + out);
      best = std::min(best, in);
      break;
    }
  }
  return best;
}

TEST(GrindTurning, SwivelledWheelFollowsItsGeneratorsToo) {
  const double w = 4.0;
  // Machine X, Z that put the wheel's centre at x = 0, z = 15 of the blank once swivelled 60 deg.
  const std::string program =
      "OP od_sharpening turn\nG0 W60\nG0 X12.990381 Y100 Z7.5\nG0 Y44\nG1 A360 F100\nG0 Y100\n";
  const GrindScene scene = testing::make_scene(kR, kL, kWheelR, w, 0.0, program);
  SectionOptions o;
  o.spacing = 0.5;
  const SectionStack stack = simulate_sections(scene, o);
  const WheelPose pose = wheel_pose(Axes{12.990381, 44, 7.5, 0, 0, 60});
  int checked = 0;
  for (const Section& s : stack.sections) {
    if (std::fmod(s.z, 1.0) != 0.0) continue;  // every second section: the scan is slow
    const double want = swivelled_ground_radius(pose, kWheelR, w, s.z);
    if (want >= kR - 0.01) continue;
    const auto [lo, hi] = radius_range(s);
    // As above, and the 180 generators' chords, R (1 - cos(pi / 180)) = 0.006 mm.
    EXPECT_NEAR(lo, want, 0.011) << "z " << s.z;
    EXPECT_NEAR(hi, want, 0.011) << "z " << s.z;
    ++checked;
  }
  EXPECT_GE(checked, 6);
}

TEST(GrindTurning, CylindricalGrindingKeepsTheRadiusAtTheDefaultStep) { expect_cylindrical_grinding(4.0, 0.25); }

// Forty turns: 5 000 increments a section, merged as they come, the removed ring (an outer boundary and a
// hole) merged again with the hulls after it. A batch holding the hole without its boundary would fill it
// and grind the core away (review: the merged regions keep them together; loose paths happened to stay
// together in this case too). The core keeps the ground radius.
TEST(GrindTurning, ManyTurnsKeepTheCore) {
  const std::string program = "OP od_sharpening turn\nG0 X0 Y100 Z2\nG0 Y44\nG1 A14400 F100\nG0 Y100\n";
  const GrindScene scene = testing::make_scene(kR, 4.0, kWheelR, 4.0, 0.0, program);
  SectionOptions o;
  o.spacing = 2.0;
  const SectionStack stack = simulate_sections(scene, o);
  ASSERT_EQ(stack.sections.size(), 3u);
  for (const Section& s : stack.sections) {
    const double want = kYc - std::sqrt(kWheelR * kWheelR - (s.z - 2) * (s.z - 2));  // 4 to 4.05
    const auto [lo, hi] = radius_range(s);
    EXPECT_NEAR(lo, want, 0.005) << "z " << s.z;
    EXPECT_NEAR(hi, want, 0.005) << "z " << s.z;
    EXPECT_NEAR(section_area(s), M_PI * want * want, 0.05) << "z " << s.z;
  }
}

TEST(GrindTurning, AWideWheelAndACoarseStepToo) { expect_cylindrical_grinding(10.0, 1.0); }

}  // namespace turning_test
}  // namespace tf::grind
