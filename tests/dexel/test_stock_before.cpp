// The stock read as it was before a change: the pieces subtract_intervals reports removed make up, with
// what it keeps, exactly the material before (slivers included), and RemovedPieces gives each ray back
// its own pieces for the current change only.
#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <vector>

#include "tiltfield/dexel/stock_before.hpp"
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

bool same(const std::vector<Interval>& a, const std::vector<Interval>& b) {
  if (a.size() != b.size()) return false;
  for (size_t k = 0; k < a.size(); ++k)
    if (a[k].lo != b[k].lo || a[k].hi != b[k].hi) return false;
  return true;
}

TEST(StockBefore, KeptAndRemovedPiecesMakeUpTheMaterialExactly) {
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
    std::vector<Interval> out, removed, back;
    const double gone = subtract_intervals(a.data(), a.size(), b.data(), b.size(), out, &removed);
    join_disjoint(out.data(), out.size(), removed.data(), removed.size(), back);
    std::vector<Interval> a_joined;  // a itself, touching intervals joined as join_disjoint does
    join_disjoint(a.data(), a.size(), nullptr, 0, a_joined);
    ASSERT_TRUE(same(back, a_joined)) << "trial " << trial;
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

TEST(StockBefore, RemovedPiecesAreThoseOfTheCurrentChangeInsideTheFootprint) {
  RemovedPieces rp;
  std::array<RemovedPieces::Footprint, 3> fp;
  fp[0] = {2, 5, 10, 12};
  fp[2] = {0, 3, 0, 3};  // grid 1 empty
  rp.start(fp, 2);
  const Interval p0[] = {{1.f, 2.f}, {4.f, 4.5f}}, p1[] = {{0.f, 0.25f}};
  rp.add(0, 0, 3, 11, p0, 2);
  rp.add(1, 2, 3, 3, p1, 1);
  EXPECT_EQ(rp.rays(), 2u);
  auto [r0, n0] = rp.removed(0, 3, 11);
  ASSERT_EQ(n0, 2u);
  EXPECT_EQ(r0[1].hi, 4.5f);
  EXPECT_EQ(rp.removed(2, 3, 3).second, 1u);
  EXPECT_EQ(rp.removed(0, 4, 11).second, 0u) << "a ray of the footprint the change did not touch";
  EXPECT_EQ(rp.removed(0, 6, 11).second, 0u) << "outside the footprint";
  EXPECT_EQ(rp.removed(1, 0, 0).second, 0u);
  EXPECT_THROW(rp.add(0, 1, 0, 0, p1, 1), std::logic_error);
  EXPECT_THROW(rp.add(2, 0, 3, 11, p1, 1), std::logic_error) << "writer 2 of 2";
  // Removed from again (a crash after the cut): both lots, in order.
  const Interval later[] = {{2.5f, 3.f}};
  rp.add(0, 0, 3, 11, later, 1);
  auto [r1, n1] = rp.removed(0, 3, 11);
  ASSERT_EQ(n1, 3u);
  EXPECT_EQ(r1[1].lo, 2.5f);
  EXPECT_EQ(rp.rays(), 2u);
  // The next change sees none of it, even where the footprint moved over the same table slots.
  fp[0] = {3, 6, 11, 13};
  rp.start(fp, 2);
  EXPECT_EQ(rp.removed(0, 3, 11).second, 0u);
  EXPECT_EQ(rp.removed(0, 4, 12).second, 0u);
  EXPECT_EQ(rp.rays(), 0u);
}

TEST(StockBefore, ReadsEachRayWithItsPiecesPutBack) {
  Lattice L;
  L.n = {4, 4, 4};
  TriDexel now(L);
  const Interval kept[] = {{0.f, 1.f}, {2.f, 3.f}};
  now.ray(2, 1, 1).assign(kept, 2);
  RemovedPieces rp;
  std::array<RemovedPieces::Footprint, 3> fp;
  fp[2] = {0, 3, 0, 3};
  rp.start(fp, 1);
  const Interval gone[] = {{1.f, 2.f}, {3.5f, 4.f}};
  rp.add(0, 2, 1, 1, gone, 2);
  std::vector<Interval> ray;
  StockBefore(now, &rp).ray(2, 1, 1, ray);
  ASSERT_EQ(ray.size(), 2u);
  EXPECT_EQ(ray[0].lo, 0.f);
  EXPECT_EQ(ray[0].hi, 3.f) << "a piece touching material on both sides joins them";
  EXPECT_EQ(ray[1].lo, 3.5f);
  StockBefore(now).ray(2, 1, 1, ray);
  EXPECT_EQ(ray.size(), 2u);
  EXPECT_EQ(ray[0].hi, 1.f) << "without pieces: the stock itself";
}

}  // namespace
}  // namespace tf
