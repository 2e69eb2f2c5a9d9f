// The engagement's material test on long rays (a raster's grooves leave hundreds of intervals on the rays
// across them, searched rather than scanned): the signed along-ray distance to the nearest material
// boundary, against the ray's intervals walked one by one.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "sampler.hpp"
#include "tiltfield/dexel/tridexel.hpp"

namespace tf {
namespace {

// Signed distance from t to the nearest boundary of sorted, disjoint intervals; +inf for none.
double reference_distance(const std::vector<Interval>& u, float t) {
  double best = std::numeric_limits<double>::infinity();
  for (const Interval& iv : u) {
    if (t >= iv.lo && t <= iv.hi) return -std::min(t - iv.lo, iv.hi - t);
    best = std::min<double>(best, t < iv.lo ? iv.lo - t : t - iv.hi);
  }
  return best;
}

TEST(MaterialDepth, LongAndShortRaysAsTheirIntervalsWalked) {
  Lattice L;
  L.h = 1.0;
  L.n = {400, 3, 3};  // the x rays run 400 mm; the y and z rays are 3 mm long, empty
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> len(0.05f, 0.6f);
  for (int trial = 0; trial < 40; ++trial) {
    TriDexel stock(L);
    std::vector<Interval> ray;
    float x = 0.5f;
    const int n = trial % 2 ? 300 : 6;  // a long ray (searched) and a short one (scanned)
    for (int k = 0; k < n && x < 390.f; ++k) {
      const float a = x, b = x + len(rng);
      ray.push_back({a, b});
      x = b + len(rng);
    }
    stock.ray(0, 1, 1).assign(ray.data(), static_cast<uint32_t>(ray.size()));
    std::uniform_real_distribution<float> at(0.f, x + 1.f);
    for (int k = 0; k < 500; ++k) {
      const Interval& edge = ray[size_t(k) % ray.size()];
      const float t = k < 100 ? (k % 2 ? edge.lo : edge.hi) : at(rng);  // on boundaries, then anywhere
      const Eigen::Vector3d p(L.origin.x() + t, L.origin.y() + 1.0, L.origin.z() + 1.0);
      ASSERT_EQ(engagement::material_depth(stock, p), reference_distance(ray, static_cast<float>(p.x() - L.origin.x())))
          << "trial " << trial << ", t " << t;
    }
  }
}

}  // namespace
}  // namespace tf
