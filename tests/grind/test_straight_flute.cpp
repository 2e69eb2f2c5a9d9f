// A straight flute ground by a disc wheel against its analytic cross-section and volume.
#include <gtest/gtest.h>

#include <polyclipping/clipper.hpp>

#include "grind_test_util.hpp"
#include "tiltfield/grind/sections.hpp"

namespace tf::grind {
namespace {

constexpr double kR = 5.0, kL = 30.0, kWheelR = 40.0, kW = 4.0, kE = 1.0, kXc = 1.0, kBottom = 2.5;
constexpr double kYc = kWheelR + kBottom, kZEnd = 20.0;  // the wheel centre stops at z = 20

// Wheel axis along x (W = 0), centre (1, 42.5, z) moving from z = 60 down to z = 20: a straight groove from
// the tip (z = 30) back to z = 20, running out below.
const char* kStraightFluteProgram = R"(
OP fluting straight flute
G0 X1 Y60 Z60
G1 Y42.5 F300
G1 Z20
G0 Y60
)";

using ClipperLib::IntPoint;
using ClipperLib::Path;
using ClipperLib::Paths;
constexpr double kS = 1e6;

// The exact section at height z: the blank circle minus the groove the wheel swept, sampled densely.
Paths analytic_section(double z, int n = 20000) {
  const double delta = std::max(0.0, kZEnd - z);  // nearest wheel centre is at z = 20 (or at z itself)
  Path circle, groove;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    circle.push_back({std::llround(kR * std::cos(a) * kS), std::llround(kR * std::sin(a) * kS)});
  }
  for (int i = 0; i <= n / 4; ++i) {
    const double t = -0.5 * kW + kW * i / (n / 4);
    const double rho = testing::wheel_rho(kWheelR, kW, kE, t);
    if (rho <= delta) continue;
    const double y = kYc - std::sqrt(rho * rho - delta * delta);
    groove.push_back({std::llround((kXc + t) * kS), std::llround(y * kS)});
  }
  Paths out;
  if (groove.size() < 2) return {circle};
  groove.push_back({groove.back().X, std::llround(20 * kS)});
  groove.push_back({groove.front().X, std::llround(20 * kS)});
  ClipperLib::Clipper c;
  c.AddPath(circle, ClipperLib::ptSubject, true);
  c.AddPath(groove, ClipperLib::ptClip, true);
  c.Execute(ClipperLib::ctDifference, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return out;
}

double seg_dist(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double t = std::clamp((p - a).dot(d) / std::max(d.squaredNorm(), 1e-30), 0.0, 1.0);
  return (p - a - t * d).norm();
}

double dist_to(const std::vector<std::vector<Eigen::Vector2d>>& polys, const Eigen::Vector2d& p) {
  double best = 1e300;
  for (const auto& poly : polys)
    for (size_t i = 0; i < poly.size(); ++i) best = std::min(best, seg_dist(p, poly[i], poly[(i + 1) % poly.size()]));
  return best;
}

double paths_area(const Paths& p) {
  double s = 0;
  for (const auto& q : p) s += ClipperLib::Area(q);
  return s / (kS * kS);
}

TEST(StraightFlute, SectionsMatchTheAnalyticGroove) {
  const GrindScene scene = testing::make_scene(kR, kL, kWheelR, kW, kE, kStraightFluteProgram);
  SectionOptions opt;
  opt.spacing = 0.5;
  const SectionStack stack = simulate_sections(scene, opt);
  // Error bound of a section: blank circle chords + wheel ring sampling + vertex cleaning + the chord of the
  // wheel's path between increments (step^2 / 8R), plus the Clipper grid.
  const double bound = opt.chord_tolerance + opt.chord_tolerance + opt.clean_tolerance +
                       opt.step * opt.step / (8 * kWheelR) + 2e-6;
  double worst = 0.0;
  for (double z : {29.0, 25.0, 20.0, 15.0, 10.0}) {
    const Section* s = nullptr;
    for (const auto& sec : stack.sections)
      if (std::abs(sec.z - z) < 1e-9) s = &sec;
    ASSERT_NE(s, nullptr);
    ASSERT_EQ(s->contours.size(), 1u) << "z = " << z;
    std::vector<std::vector<Eigen::Vector2d>> sim{s->contours[0].points}, exact;
    const Paths a = analytic_section(z);
    for (const auto& p : a) {
      exact.emplace_back();
      for (const auto& q : p) exact.back().emplace_back(q.X / kS, q.Y / kS);
    }
    double d = 0;
    for (const auto& p : sim[0]) d = std::max(d, dist_to(exact, p));
    for (size_t i = 0; i < exact[0].size(); i += 7) d = std::max(d, dist_to(sim, exact[0][i]));
    worst = std::max(worst, d);
    EXPECT_LE(d, bound) << "z = " << z;
    EXPECT_NEAR(section_area(*s), paths_area(a), 20 * bound) << "z = " << z;
    // The groove's edges carry the flute's label, the rest the blank's.
    int flute_edges = 0;
    for (int l : s->contours[0].labels) flute_edges += l == 1;
    EXPECT_GT(flute_edges, 5);
  }
  RecordProperty("max_section_deviation_mm", std::to_string(worst));
  std::printf("straight flute: max section deviation %.5f mm (bound %.5f mm)\n", worst, bound);
}

TEST(StraightFlute, MeshVolumeMatchesTheAnalyticIntegral) {
  const GrindScene scene = testing::make_scene(kR, kL, kWheelR, kW, kE, kStraightFluteProgram);
  SectionOptions opt;
  opt.spacing = 0.1;
  const SectionStack stack = simulate_sections(scene, opt);
  const Mesh mesh = tile_sections(stack);
  ASSERT_TRUE(is_closed(mesh));
  const double blank_area = section_area(stack.sections.front());  // z = 0 is untouched: the blank polygon
  ASSERT_NEAR(blank_area, M_PI * kR * kR, 0.05);
  const double removed_mesh = blank_area * kL - signed_volume(mesh);
  // Analytic removed volume: integral of the exact removed area over z (fine Simpson rule).
  const int n = 300;
  double removed_exact = 0;
  for (int i = 0; i <= n; ++i) {
    const double z = kL * i / n, w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    removed_exact += w * (M_PI * kR * kR - paths_area(analytic_section(z, 2000)));
  }
  removed_exact *= kL / n / 3;
  const double rel = std::abs(removed_mesh - removed_exact) / removed_exact;
  std::printf("straight flute: removed volume mesh %.4f mm3, analytic %.4f mm3, rel. error %.5f\n", removed_mesh,
              removed_exact, rel);
  EXPECT_LT(rel, 0.005);
  EXPECT_FALSE(testing::self_intersects(mesh));
}

// A wheel face exactly in a section plane (the swivel W90 leaves cos 90 deg = 6e-17 in the wheel's axis) is
// ground like a face a micrometre past the plane: the whole section, not the half on one side that the
// rounding's sign picked (found by black-box testing). The same at the blank's tip, the last section.
TEST(StraightFlute, WheelFaceExactlyOnASectionPlaneGrindsTheWholeSection) {
  SectionOptions o;
  o.spacing = 0.25;
  for (const double face_z : {0.5, 1.0}) {
    SCOPED_TRACE(face_z);
    auto section_at = [&](double x) {
      const GrindScene scene = testing::make_scene(2, 1, 10, 2, 0, "OP end_face face\nG1 Y0\n", {x, 30, 0, 0, 0, 90});
      const SectionStack stack = simulate_sections(scene, o);
      for (const Section& sec : stack.sections)
        if (std::abs(sec.z - face_z) < 1e-9) return section_area(sec);
      ADD_FAILURE() << "no section at " << face_z;
      return -1.0;
    };
    // The wheel's lower face lies at z = x - 1: below the plane by 1e-6, on it, above it by 1e-6.
    const double past = section_at(face_z + 1.0 - 1e-6), on = section_at(face_z + 1.0), short_of = section_at(face_z + 1.0 + 1e-6);
    EXPECT_NEAR(short_of, M_PI * 4, 0.03);  // untouched (the circle polygonised within its chord tolerance)
    EXPECT_NEAR(past, 0.0, 1e-6);           // ground away
    EXPECT_NEAR(on, past, 1e-6);
  }
}

}  // namespace
}  // namespace tf::grind
