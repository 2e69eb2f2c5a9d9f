// The stock read as it was before a change: the pieces subtract_intervals reports removed make up, with
// what it keeps, exactly the material before (slivers included), and RemovedPieces gives each ray back
// its own pieces, or its material before (a short ray kept whole), for the current change only.
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
  const RemovedPieces::Kept k0 = rp.kept(0, 3, 11);
  ASSERT_EQ(k0.n, 2u);
  EXPECT_FALSE(k0.whole);
  EXPECT_EQ(k0.p[1].hi, 4.5f);
  EXPECT_EQ(rp.kept(2, 3, 3).n, 1u);
  EXPECT_EQ(rp.kept(0, 4, 11).n, 0u) << "a ray of the footprint the change did not touch";
  EXPECT_EQ(rp.kept(0, 6, 11).n, 0u) << "outside the footprint";
  EXPECT_EQ(rp.kept(1, 0, 0).n, 0u);
  EXPECT_THROW(rp.add(0, 1, 0, 0, p1, 1), std::logic_error);
  EXPECT_THROW(rp.add(2, 0, 3, 11, p1, 1), std::logic_error) << "writer 2 of 2";
  // Removed from again (a crash after the cut): both lots, in order.
  const Interval later[] = {{2.5f, 3.f}};
  rp.add(0, 0, 3, 11, later, 1);
  const RemovedPieces::Kept k1 = rp.kept(0, 3, 11);
  ASSERT_EQ(k1.n, 3u);
  EXPECT_EQ(k1.p[1].lo, 2.5f);
  EXPECT_EQ(rp.rays(), 2u);
  // The next change sees none of it, even where the footprint moved over the same table slots.
  fp[0] = {3, 6, 11, 13};
  rp.start(fp, 2);
  EXPECT_EQ(rp.kept(0, 3, 11).n, 0u);
  EXPECT_EQ(rp.kept(0, 4, 12).n, 0u);
  EXPECT_EQ(rp.rays(), 0u);
}

TEST(StockBefore, AShortRayIsKeptWholeAndOnlyItsFirstMaterialCounts) {
  RemovedPieces rp;
  std::array<RemovedPieces::Footprint, 3> fp;
  fp[1] = {0, 3, 0, 3};
  rp.start(fp, 1);
  const Interval before[] = {{0.f, 5.f}}, after_first[] = {{0.f, 2.f}};
  rp.add_before(0, 1, 2, 2, before, 1);
  rp.add_before(0, 1, 2, 2, after_first, 1);  // removed from again: the first record is the ray before
  const RemovedPieces::Kept k = rp.kept(1, 2, 2);
  ASSERT_EQ(k.n, 1u);
  EXPECT_TRUE(k.whole);
  EXPECT_EQ(k.p[0].hi, 5.f);
  const Interval piece[] = {{1.f, 2.f}};
  rp.add(0, 1, 2, 2, piece, 1);
  EXPECT_EQ(rp.kept(1, 2, 2).p[0].hi, 5.f) << "pieces after a whole record add nothing";
  // Pieces first (a long ray), then the ray short enough to be kept whole: the two joined.
  const Interval gone[] = {{3.f, 4.f}}, rest[] = {{0.f, 1.f}, {4.f, 6.f}};
  rp.add(0, 1, 3, 3, gone, 1);
  rp.add_before(0, 1, 3, 3, rest, 2);
  const RemovedPieces::Kept j = rp.kept(1, 3, 3);
  ASSERT_EQ(j.n, 2u);
  EXPECT_TRUE(j.whole);
  EXPECT_EQ(j.p[1].lo, 3.f);
  EXPECT_EQ(j.p[1].hi, 6.f);
  rp.add_before(0, 1, 0, 0, before, 0);  // a ray without material: nothing to keep
  EXPECT_EQ(rp.kept(1, 0, 0).n, 0u);
  EXPECT_EQ(rp.rays(), 2u);
  EXPECT_THROW(rp.add_before(0, 0, 0, 0, before, 1), std::logic_error) << "grid 0's footprint is empty";
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
  // Kept whole: the record itself, whatever the ray holds now.
  const Interval was[] = {{0.f, 4.f}};
  rp.add_before(0, 2, 2, 2, was, 1);
  StockBefore(now, &rp).ray(2, 2, 2, ray);
  ASSERT_EQ(ray.size(), 1u);
  EXPECT_EQ(ray[0].hi, 4.f);
}

}  // namespace
}  // namespace tf
