// The pieces subtract_intervals reports removed (the gouge check reads them) make up, with what it keeps,
// exactly the material before, slivers included.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "tiltfield/dexel/tridexel.hpp"

namespace tf {
namespace {

// Sorted disjoint intervals with gaps and lengths drawn from [lo_len, hi_len] (mm), from x = 0.
std::vector<Interval> random_list(std::mt19937& rng, int n, float lo_len, float hi_len) {
  std::uniform_real_distribution<float> len(lo_len, hi_len);
  std::vector<Interval> v;
  float x = 0.f;
  for (int k = 0; k < n; ++k) {
    x += len(rng);
    const float lo = x;
    x += len(rng);
    v.push_back({lo, x});
  }
  return v;
}

// The union of two sorted lists of disjoint intervals that do not overlap each other's (they may touch),
// touching intervals joined.
std::vector<Interval> joined(const std::vector<Interval>& a, const std::vector<Interval>& b) {
  std::vector<Interval> out;
  size_t i = 0, j = 0;
  while (i < a.size() || j < b.size()) {
    const Interval& x = j >= b.size() || (i < a.size() && a[i].lo <= b[j].lo) ? a[i++] : b[j++];
    if (!out.empty() && x.lo <= out.back().hi) out.back().hi = std::max(out.back().hi, x.hi);
    else out.push_back(x);
  }
  return out;
}

bool same(const std::vector<Interval>& a, const std::vector<Interval>& b) {
  if (a.size() != b.size()) return false;
  for (size_t k = 0; k < a.size(); ++k)
    if (a[k].lo != b[k].lo || a[k].hi != b[k].hi) return false;
  return true;
}

TEST(SubtractIntervals, KeptAndRemovedPiecesMakeUpTheMaterialExactly) {
  std::mt19937 rng(7);
  int slivers = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const std::vector<Interval> a = random_list(rng, 1 + trial % 9, 1e-3f, 0.5f);
    std::vector<Interval> b = random_list(rng, 1 + trial % 5, 1e-3f, 0.7f);
    // Every third trial a cut that leaves a sliver under kMinInterval at both ends of a material interval.
    if (trial % 3 == 0) {
      const Interval& m = a[size_t(trial) % a.size()];
      b = {{m.lo + 0.3f * kMinInterval, m.hi - 0.4f * kMinInterval}};
    }
    std::vector<Interval> out, removed;
    const double gone = subtract_intervals(a.data(), a.size(), b.data(), b.size(), out, &removed);
    ASSERT_TRUE(same(joined(out, removed), joined(a, {}))) << "trial " << trial;
    double len = 0.0;
    for (const Interval& r : removed) len += double(r.hi) - double(r.lo);
    EXPECT_NEAR(len, gone, 1e-5) << "trial " << trial;
    for (size_t k = 0; k + 1 < out.size(); ++k) ASSERT_LT(out[k].hi, out[k + 1].lo);
    for (const Interval& o : out) slivers += o.hi - o.lo <= kMinInterval;
    if (trial % 3 == 0) {
      EXPECT_EQ(removed.size(), 1u) << "the slivers joined to the cut, trial " << trial;
    }
  }
  EXPECT_EQ(slivers, 0) << "no kept piece is a sliver";
}

// Dexel::replace against the list put together: inline, heap in place and grown storage, at the front,
// the middle and the end.
TEST(Dexel, ReplaceKeepsTheOtherIntervals) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 3000; ++trial) {
    const std::vector<Interval> a = random_list(rng, trial % 7, 0.01f, 0.5f);  // 0 to 6 intervals
    Dexel ray;
    ray.assign(a.data(), static_cast<uint32_t>(a.size()));
    if (trial % 3 == 0 && !a.empty()) ray.assign(a.data(), 1), ray.assign(a.data(), static_cast<uint32_t>(a.size()));
    const uint32_t k0 = a.empty() ? 0 : uint32_t(rng() % (a.size() + 1));
    const uint32_t k1 = k0 + (a.size() > k0 ? uint32_t(rng() % (a.size() - k0 + 1)) : 0);
    // New intervals inside the gap the replaced ones leave: between a[k0 - 1] and a[k1].
    const float lo = k0 > 0 ? a[k0 - 1].hi + 0.001f : -10.f, hi = k1 < a.size() ? a[k1].lo - 0.001f : 10.f;
    std::vector<Interval> mid;
    const int m = int(rng() % 4);
    for (int k = 0; k < m; ++k) {
      const float x0 = lo + (hi - lo) * (2 * k + 0.2f) / (2 * m), x1 = lo + (hi - lo) * (2 * k + 1.0f) / (2 * m);
      mid.push_back({x0, x1});
    }
    std::vector<Interval> want(a.begin(), a.begin() + k0);
    want.insert(want.end(), mid.begin(), mid.end());
    want.insert(want.end(), a.begin() + k1, a.end());
    ray.replace(k0, k1, mid.data(), static_cast<uint32_t>(mid.size()));
    ASSERT_TRUE(same(std::vector<Interval>(ray.begin(), ray.end()), want)) << "trial " << trial;
  }
}

}  // namespace
}  // namespace tf
