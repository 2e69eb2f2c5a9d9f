// Randomised profiles (star-shaped chains of lines and arcs, short and LONG arcs, both turning senses):
// every valid profile's offset matches Clipper's area and contour count, is exact, and is clean; sharp
// corners and variable gaps keep their guarantees too.
#include <random>

#include "offset_test_util.hpp"
#include "tiltfield/core/error.hpp"

namespace tf::offset::test {
namespace {

std::string random_profile(std::mt19937& rng) {
  std::uniform_real_distribution<double> U(0, 1);
  const int n = 4 + static_cast<int>(rng() % 20);
  std::vector<double> ang;
  for (int k = 0; k < n; ++k) ang.push_back(U(rng) * 2 * M_PI);
  std::sort(ang.begin(), ang.end());
  std::vector<Eigen::Vector2d> P;
  for (double a : ang) {
    const double r = 20 + 40 * U(rng);
    P.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  std::ostringstream s;
  s.precision(17);
  s << "START " << P[0].x() << " " << P[0].y() << "\n";
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector2d d = P[(k + 1) % n] - P[k];
    double R = 0;
    if (rng() % 2) R = (rng() % 2 ? 1 : -1) * d.norm() * (0.51 + 4 * U(rng));
    s << R << " " << d.x() << " " << d.y() << (R != 0 && rng() % 8 == 0 ? " LONG" : "") << "\n";
  }
  return s.str();
}

TEST(OffsetRandom, MatchesClipperAndStaysExact) {
  std::mt19937 rng(2024);
  int checked = 0;
  for (int it = 0; it < 120 && checked < 50; ++it) {
    const std::string text = random_profile(rng);
    Profile p;
    try {
      p = profile_text(text);
    } catch (const InputError&) {
      continue;  // self-crossing draws are rejected, as they must be
    }
    const double gap = 0.2 + 12 * std::uniform_real_distribution<double>(0, 1)(rng);
    OffsetOptions o;
    o.side = rng() % 2 ? Side::Inside : Side::Outside;
    SCOPED_TRACE("gap " + std::to_string(gap) + (o.side == Side::Inside ? " inside\n" : " outside\n") + text);
    const auto r = offset_profile(p, constant_gap(gap), o);
    const auto ref = clipper_offset(p, gap, o.side);
    EXPECT_EQ(static_cast<int>(r.contours.size()), ref.contours);
    // Polygonisation at 0.001 mm loses up to ~(2/3) * 0.001 mm times the arcs' length in area.
    const double a = std::abs(total_area(r)), b = std::abs(ref.area);
    EXPECT_LE(std::abs(a - b), 1e-4 * b + 1e-3 * chain_length(p.elements));
    EXPECT_LE(check_exactness(p, constant_gap(gap), r, 16).max_error, 1e-6);
    expect_clean_contours(r);
    ++checked;
  }
  EXPECT_GE(checked, 20);
}

TEST(OffsetRandom, SharpCornersAndGapLaws) {
  std::mt19937 rng(77);
  int checked = 0;
  for (int it = 0; it < 100 && checked < 30; ++it) {
    const std::string text = random_profile(rng);
    Profile p;
    try {
      p = profile_text(text);
    } catch (const InputError&) {
      continue;
    }
    const double gap = 0.2 + 8 * std::uniform_real_distribution<double>(0, 1)(rng);
    OffsetOptions o;
    o.side = rng() % 2 ? Side::Inside : Side::Outside;
    o.corner = Corner::Sharp;
    SCOPED_TRACE("gap " + std::to_string(gap) + (o.side == Side::Inside ? " inside\n" : " outside\n") + text);
    const auto r = offset_profile(p, constant_gap(gap), o);
    const auto e = check_exactness(p, constant_gap(gap), r, 16);
    EXPECT_LE(e.max_error, 1e-6);
    EXPECT_GE(e.min_sharp, -1e-6);
    expect_clean_contours(r);

    const double L = chain_length(p.elements);
    GapLaw law;
    law.s = {0};
    law.gap = {gap};
    const int knots = 1 + static_cast<int>(rng() % 4);
    double gmin = gap, gmax = gap;
    for (int k = 1; k <= knots; ++k) {
      law.s.push_back(L * k / (knots + 1));
      law.gap.push_back(gap * (0.6 + 0.8 * std::uniform_real_distribution<double>(0, 1)(rng)));
      gmin = std::min(gmin, law.gap.back());
      gmax = std::max(gmax, law.gap.back());
    }
    law.s.push_back(L);
    law.gap.push_back(gap);
    law.blend = rng() % 2 ? 2.0 : 0.0;
    o.corner = rng() % 2 ? Corner::Sharp : Corner::Round;
    const auto r2 = offset_profile(p, law, o);
    const auto e2 = check_exactness(p, law, r2, 16);
    EXPECT_LE(e2.max_error, 1e-6);
    EXPECT_LE(e2.max_fitted, 1e-6);
    EXPECT_GE(e2.min_sharp, -1e-6);
    EXPECT_GE(e2.min_transition, -(gmax - gmin) - 1e-6);
    expect_clean_contours(r2);
    ++checked;
  }
  EXPECT_GE(checked, 15);
}

}  // namespace
}  // namespace tf::offset::test
