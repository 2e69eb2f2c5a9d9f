// The simulation's engagement hook (VerifyOptions::engagement): called after each feed block that removed
// material next to the tool's end pose, with the stock as it was before that block wherever the
// engagement reads it (the rays near the end pose's cutting surface, where the cut defers its changes
// until the hook returns), the block's poses, and a box holding what the block removed there. The reference for
// "before block k" is the same program cut off after block k - 1, simulated on its own.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <stdexcept>
#include <vector>

#include "helpers.hpp"
#include "moves.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf {
namespace {

// The rays the engagement reads: those whose line passes within the tool's radius and 1.5 spacings of the
// cutting part's axis segment (tip to the flutes' top) at `end`, inside the box of the cylinder of that
// radius about the segment (all the cutting surface lies in the cylinder; a ray read is at most 0.71
// spacings from a point of it).
struct Footprint {
  Eigen::Vector3d tip, top;
  double radius, reach;
  bool holds(int d, const Lattice& L, int iu, int iv) const {
    const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
    Eigen::Vector3d p = L.origin;
    p[u] += L.h * iu;
    p[v] += L.h * iv;
    // The box: a disc of radius r normal to unit axis a spans r sqrt(1 - a_k^2) along axis k.
    const Eigen::Vector3d a = (top - tip).normalized();
    for (int k : {u, v}) {
      const double ext = radius * std::sqrt(std::max(0.0, 1.0 - a[k] * a[k])) + (reach - radius);
      if (p[k] < std::min(tip[k], top[k]) - ext || p[k] > std::max(tip[k], top[k]) + ext) return false;
    }
    // The line through p along axis d: its distance to a point of the segment is the distance across
    // axis d, so the closest point of the segment is found in that plane.
    Eigen::Vector3d s0 = tip - p, s1 = top - p;
    s0[d] = 0.0, s1[d] = 0.0;
    const Eigen::Vector3d e = s1 - s0;
    const double t = e.squaredNorm() > 0 ? std::clamp(-s0.dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
    return (s0 + t * e).norm() <= reach;
  }
};

Footprint reads_of(const Tool& tool, const ToolPose& end, double h) {
  return {end.tip, end.tip + tool.flute_length * end.axis.normalized(), tool.radius(), tool.radius() + 1.5 * h};
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

// Runs `program` with a hook that keeps every stock it is given, then compares each with the program cut
// off before that block.
void expect_stock_before_each_block(const Scene& s, const Program& program, const ForwardFn& forward) {
  struct Call {
    int block;  // 1-based, from the end pose
    TriDexel stock;
    Footprint reads;
    Eigen::AlignedBox3d removed;
  };
  std::deque<Call> calls;  // not moved once made
  VerifyOptions o;
  o.resolution = 0.2;
  o.engagement = [&](const Tool& tool, const TriDexel& stock, const ToolPose&, const ToolPose& end,
                     const Eigen::AlignedBox3d& removed) {
    const Lattice& L = stock.lattice();
    Call& c = calls.emplace_back(Call{0, TriDexel(L), reads_of(tool, end, L.h), removed});
    for (int d = 0; d < 3; ++d)
      for (int iv = 0; iv < L.n[Lattice::v_axis(d)]; ++iv)
        for (int iu = 0; iu < L.n[Lattice::u_axis(d)]; ++iu) {
          const Dexel& ray = stock.ray(d, iu, iv);
          c.stock.ray(d, iu, iv).assign(ray.begin(), ray.size());
        }
    return Engagement{};
  };
  const VerifyResult r = verify_program(s, program, forward, o);
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
    return verify_program(s, cut, forward, plain).stock;
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

// A plunge, a slot, a cut across it, a move in air (removes nothing), a short move (under a spacing).
Program hook_program() {
  return test::Moves()
      .rapid({-5, 10, 18})
      .line({.x = 20}, 800)
      .line({.y = 25})
      .line({.x = 35, .y = 5, .z = 16})
      .line({.z = 30})
      .line({.x = 5, .y = 5})
      .line({.z = 16.5})
      .line({.x = 5.05})
      .program();
}

TEST(EngagementHook, SeesTheStockBeforeEachBlockWhereItReadsAndABoxHoldingTheRemoval) {
  const Scene s = test::box_scene({0, 0, 0}, {40, 30, 20}, test::ball_tool(3, 12, 3, 30, {{10, 30}}));
  expect_stock_before_each_block(s, hook_program(), forward_xyz);
}

// The same with the axis leaning 30 deg (in x and y): the rays read are a slanted band across each grid,
// not the box around it.
TEST(EngagementHook, SeesTheStockBeforeEachBlockWithALeaningAxis) {
  const Scene s = test::box_scene({0, 0, 0}, {40, 30, 20}, test::ball_tool(3, 12, 3, 30, {{10, 30}}));
  const Eigen::Vector3d axis = Eigen::Vector3d(-0.35355, 0.35355, 0.86603).normalized();
  const ForwardFn leaning = [axis](const Joints& j) { return ToolPose{Eigen::Vector3d(j.x, j.y, j.z), axis}; };
  expect_stock_before_each_block(s, hook_program(), leaning);
}

// Each result lands in the block it was measured for (the probe answers with its end pose), blocks it was
// not called for keep an empty engagement, and an error the probe throws ends the run with that error.
TEST(EngagementHook, EachResultLandsInItsOwnBlockAndAnErrorEndsTheRun) {
  const Scene s = test::box_scene({0, 0, 0}, {40, 30, 20}, test::ball_tool(3, 12, 3, 30, {{10, 30}}));
  const Program program = hook_program();
  VerifyOptions o;
  o.resolution = 0.2;
  int calls = 0;
  o.engagement = [&](const Tool&, const TriDexel&, const ToolPose&, const ToolPose& end, const Eigen::AlignedBox3d&) {
    ++calls;
    Engagement e;
    e.area_mm2 = end.tip.x() + 100.0 * end.tip.y() + 10000.0 * end.tip.z();
    return e;
  };
  const VerifyResult r = verify_program(s, program, forward_xyz, o);
  int engaged = 0;
  for (size_t i = 0; i < r.report.per_block.size(); ++i) {
    const BlockResult& b = r.report.per_block[i];
    const Joints& t = program.blocks[i].target;
    if (!b.rapid && b.removed_mm3 > 0.0) {
      ++engaged;
      EXPECT_NEAR(b.engagement.area_mm2, t.x + 100.0 * t.y + 10000.0 * t.z, 1e-6) << "block " << b.block;
    } else {
      EXPECT_EQ(b.engagement.area_mm2, 0.0) << "block " << b.block;
    }
  }
  EXPECT_EQ(engaged, calls);
  EXPECT_GE(calls, 4);

  int seen = 0;
  o.engagement = [&](const Tool&, const TriDexel&, const ToolPose&, const ToolPose&, const Eigen::AlignedBox3d&) {
    if (++seen == 2) throw std::runtime_error("probe failed");
    return Engagement{};
  };
  EXPECT_THROW(verify_program(s, program, forward_xyz, o), std::runtime_error);
}

}  // namespace
}  // namespace tf
