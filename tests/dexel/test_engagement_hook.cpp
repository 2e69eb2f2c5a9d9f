// The simulation's engagement hook (VerifyOptions::engagement): called after each feed block that removed
// material, with the stock exactly as it was before that block (the rays the cut changed are swapped
// back from their journal for the call), the block's poses, and a box holding everything the block
// removed. Checked against the simulation's own per-block removal and a plain copy of the stock.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "helpers.hpp"
#include "moves.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf {
namespace {

// The material of `a` that `b` lacks lies inside `box` (part frame) grown by `slack` mm: every ray that
// differs has its node within the box's footprint and the same material as before outside the box.
bool removed_within(const TriDexel& a, const TriDexel& b, const Eigen::AlignedBox3d& box, double slack) {
  const Lattice& L = a.lattice();
  const Eigen::AlignedBox3d grown(box.min().array() - slack, box.max().array() + slack);
  // Length of a ray's material outside [lo, hi].
  auto outside = [](const Dexel& r, double lo, double hi) {
    double len = 0.0;
    for (const Interval& x : r)
      len += (x.hi - x.lo) - std::max(0.0, std::min<double>(hi, x.hi) - std::max<double>(lo, x.lo));
    return len;
  };
  for (int d = 0; d < 3; ++d) {
    const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
    for (int iv = 0; iv < L.n[v]; ++iv)
      for (int iu = 0; iu < L.n[u]; ++iu) {
        const Dexel& ra = a.ray(d, iu, iv);
        const Dexel& rb = b.ray(d, iu, iv);
        const bool same = ra.size() == rb.size() && std::equal(ra.begin(), ra.end(), rb.begin(), [](const Interval& x, const Interval& y) {
                            return x.lo == y.lo && x.hi == y.hi;
                          });
        if (same) continue;
        const double pu = L.origin[u] + L.h * iu, pv = L.origin[v] + L.h * iv;
        if (pu < grown.min()[u] || pu > grown.max()[u] || pv < grown.min()[v] || pv > grown.max()[v]) return false;
        const double lo = grown.min()[d] - L.origin[d], hi = grown.max()[d] - L.origin[d];
        if (std::abs(outside(ra, lo, hi) - outside(rb, lo, hi)) > 1e-5) return false;
      }
  }
  return true;
}

TEST(EngagementHook, SeesTheStockBeforeEachBlockAndABoxHoldingItsRemoval) {
  const Scene s = test::box_scene({0, 0, 0}, {40, 30, 20}, test::ball_tool(3, 12, 3, 30, {{10, 30}}));
  // A plunge, a slot, a cut across it, an arc-free 5-axis free move in air (removes nothing), a short
  // move (under a lattice spacing).
  const test::Moves moves = test::Moves()
                                .rapid({-5, 10, 18})
                                .line({.x = 20}, 800)
                                .line({.y = 25})
                                .line({.x = 35, .y = 5, .z = 16})
                                .line({.z = 30})
                                .line({.x = 5, .y = 5})
                                .line({.z = 16.5})
                                .line({.x = 5.05});
  std::vector<double> volumes;             // of the stock each call received
  std::vector<TriDexel> before_copies;     // an independent copy of it, made at the call
  std::vector<Eigen::AlignedBox3d> boxes;  // the removed boxes
  VerifyOptions o;
  o.resolution = 0.2;
  o.engagement = [&](const Tool&, const TriDexel& stock, const ToolPose&, const ToolPose&, const Eigen::AlignedBox3d& removed) {
    volumes.push_back(stock.volume());
    TriDexel copy(stock.lattice());
    for (int d = 0; d < 3; ++d)
      for (size_t k = 0; k < stock.grid(d).size(); ++k)
        copy.grid(d)[k].assign(stock.grid(d)[k].data(), stock.grid(d)[k].size());
    before_copies.push_back(std::move(copy));
    boxes.push_back(removed);
    return Engagement{};
  };
  const VerifyResult r = verify_program(s, moves.program(), forward_xyz, o);
  // The calls: one per feed block that removed material, in order; the rapid and the blocks in air none.
  std::vector<int> removing;
  double start = r.report.stock_volume_start_mm3;
  std::vector<double> expected;
  for (const BlockResult& b : r.report.per_block) {
    if (!b.rapid && b.removed_mm3 > 0.0) {
      removing.push_back(b.block);
      expected.push_back(start);
    }
    start -= b.removed_mm3;
  }
  ASSERT_GE(removing.size(), 4u);
  ASSERT_EQ(volumes.size(), removing.size());
  for (size_t k = 0; k < volumes.size(); ++k)
    EXPECT_NEAR(volumes[k], expected[k], 1e-6 * expected[k]) << "call " << k << " (block " << removing[k] << ")";
  // Each call's stock minus the next call's (or the final stock) went only inside the call's box: the
  // box is grown by a spacing, the rays' half-width around the material they represent.
  for (size_t k = 0; k < before_copies.size(); ++k) {
    const TriDexel& after = k + 1 < before_copies.size() ? before_copies[k + 1] : r.stock;
    // Blocks between two calls removed nothing, so the next call's stock is this block's result.
    EXPECT_TRUE(removed_within(before_copies[k], after, boxes[k], r.stock.lattice().h)) << "call " << k;
    EXPECT_FALSE(boxes[k].isEmpty());
  }
}

}  // namespace
}  // namespace tf
