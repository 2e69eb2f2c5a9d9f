// The simulation's engagement hook (VerifyOptions::engagement): called after each feed block that removed
// material next to the tool's end pose, with the stock as it was before that block wherever the
// engagement reads it (the rays near the end pose's cutting surface, read with the pieces the block
// removed from them put back), the block's poses, and a box holding what the block removed there. The reference for
// "before block k" is the same program cut off after block k - 1, simulated on its own.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <vector>

#include "helpers.hpp"
#include "moves.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf {
namespace {

// Per grid, the (u, v) range of the rays within 1.5 spacings of the cutting surface at `end` (the rays
// the engagement reads).
struct Footprint {
  Eigen::AlignedBox3d box;
  bool holds(int d, const Lattice& L, int iu, int iv) const {
    const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
    const double pu = L.origin[u] + L.h * iu, pv = L.origin[v] + L.h * iv;
    return pu >= box.min()[u] && pu <= box.max()[u] && pv >= box.min()[v] && pv <= box.max()[v];
  }
};

Footprint reads_of(const Tool& tool, const ToolPose& end, double h) {
  const Eigen::Vector3d a = end.axis.normalized(), top = end.tip + tool.flute_length * a;
  const Eigen::Vector3d ext =
      (Eigen::Vector3d::Ones() - a.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt() * tool.radius() + Eigen::Vector3d::Constant(1.5 * h);
  return {Eigen::AlignedBox3d(end.tip.cwiseMin(top) - ext, end.tip.cwiseMax(top) + ext)};
}

bool same_ray(const Dexel& a, const Dexel& b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](const Interval& x, const Interval& y) { return x.lo == y.lo && x.hi == y.hi; });
}

// Within `reads`, the material of `a` that `b` lacks lies inside `box` (part frame) grown by `slack` mm:
// every ray there that differs has its node within the box's footprint and the same material as before
// outside the box.
bool removed_within(const TriDexel& a, const TriDexel& b, const Eigen::AlignedBox3d& box, double slack,
                    const Footprint& reads) {
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
        if (same || !reads.holds(d, L, iu, iv)) continue;
        const double pu = L.origin[u] + L.h * iu, pv = L.origin[v] + L.h * iv;
        if (pu < grown.min()[u] || pu > grown.max()[u] || pv < grown.min()[v] || pv > grown.max()[v]) return false;
        const double lo = grown.min()[d] - L.origin[d], hi = grown.max()[d] - L.origin[d];
        if (std::abs(outside(ra, lo, hi) - outside(rb, lo, hi)) > 1e-5) return false;
      }
  }
  return true;
}

TEST(EngagementHook, SeesTheStockBeforeEachBlockWhereItReadsAndABoxHoldingTheRemoval) {
  const Scene s = test::box_scene({0, 0, 0}, {40, 30, 20}, test::ball_tool(3, 12, 3, 30, {{10, 30}}));
  // A plunge, a slot, a cut across it, a move in air (removes nothing), a short move (under a spacing).
  const test::Moves moves = test::Moves()
                                .rapid({-5, 10, 18})
                                .line({.x = 20}, 800)
                                .line({.y = 25})
                                .line({.x = 35, .y = 5, .z = 16})
                                .line({.z = 30})
                                .line({.x = 5, .y = 5})
                                .line({.z = 16.5})
                                .line({.x = 5.05});
  const Program program = moves.program();
  struct Call {
    int block;  // 1-based, from the end pose
    TriDexel stock;
    Footprint reads;
    Eigen::AlignedBox3d removed;
  };
  std::deque<Call> calls;  // not moved once made
  VerifyOptions o;
  o.resolution = 0.2;
  o.engagement = [&](const Tool& tool, const StockBefore& stock, const ToolPose&, const ToolPose& end,
                     const Eigen::AlignedBox3d& removed) {
    const Lattice& L = stock.lattice();
    Call& c = calls.emplace_back(Call{0, TriDexel(L), reads_of(tool, end, L.h), removed});
    std::vector<Interval> ray;
    for (int d = 0; d < 3; ++d)
      for (int iv = 0; iv < L.n[Lattice::v_axis(d)]; ++iv)
        for (int iu = 0; iu < L.n[Lattice::u_axis(d)]; ++iu) {
          stock.ray(d, iu, iv, ray);
          c.stock.ray(d, iu, iv).assign(ray.data(), static_cast<uint32_t>(ray.size()));
        }
    return Engagement{};
  };
  const VerifyResult r = verify_program(s, program, forward_xyz, o);
  // The calls: the feed blocks that removed material, in order; the rapid and the move in air none.
  std::vector<int> removing;
  for (const BlockResult& b : r.report.per_block)
    if (!b.rapid && b.removed_mm3 > 0.0) removing.push_back(b.block);
  ASSERT_EQ(calls.size(), removing.size());
  ASSERT_GE(calls.size(), 4u);
  auto stock_after = [&](int blocks) {  // the program cut off after `blocks` blocks, on its own
    Program cut = program;
    cut.blocks.resize(size_t(blocks));
    VerifyOptions plain;
    plain.resolution = o.resolution;
    return verify_program(s, cut, forward_xyz, plain).stock;
  };
  for (size_t k = 0; k < calls.size(); ++k) {
    const int block = removing[k];
    const TriDexel before = stock_after(block - 1), after = stock_after(block);
    const Lattice& L = before.lattice();
    size_t read = 0, differ = 0;
    for (int d = 0; d < 3; ++d)
      for (int iv = 0; iv < L.n[Lattice::v_axis(d)]; ++iv)
        for (int iu = 0; iu < L.n[Lattice::u_axis(d)]; ++iu) {
          if (!calls[k].reads.holds(d, L, iu, iv)) continue;
          ++read;
          differ += !same_ray(calls[k].stock.ray(d, iu, iv), before.ray(d, iu, iv));
        }
    EXPECT_GT(read, 100u);
    EXPECT_EQ(differ, 0u) << "block " << block << ": rays the engagement reads are not as before the block";
    EXPECT_FALSE(calls[k].removed.isEmpty());
    EXPECT_TRUE(removed_within(before, after, calls[k].removed, L.h, calls[k].reads)) << "block " << block;
  }
}

}  // namespace
}  // namespace tf
