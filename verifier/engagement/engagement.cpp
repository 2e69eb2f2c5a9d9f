// Cutter-workpiece engagement at a block's end by sampling the cutting surface against the in-process
// tri-dexel stock (include/tiltfield/engagement/engagement.hpp has the method and the angle convention).
#include "tiltfield/engagement/engagement.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <utility>
#include <variant>
#include <vector>

#include "rings.hpp"
#include "sampler.hpp"
#include "tiltfield/core/internal/vector_clones.hpp"

namespace tf {

namespace {

using engagement::BlockSamples;
using engagement::cos_range;
using engagement::Extent;
using engagement::kPi;
using engagement::kRefineFraction;
using engagement::kRingGrain;
using engagement::PointState;
using engagement::Profile;
using engagement::ProfilePoint;
using engagement::RingFrame;
using engagement::RingResult;
using engagement::SampleGrid;
using engagement::Sampler;
constexpr double kDeg = 180.0 / kPi;

// The rings whose band (to the neighbouring rings, which their refinement may reach) meets the region.
void active_rings(const SampleGrid& g, const Sampler& sampler, BlockSamples& b) {
  const engagement::Frame& f = sampler.end_frame();
  // A circle of radius r about axis a spans r sqrt(1 - a_k^2) along axis k.
  const Eigen::Vector3d span = (Eigen::Vector3d::Ones() - f.e3.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt();
  // Every point of the cutting surface at height z along the axis lies at z from the frame's origin along
  // e3, and every point of the region within `reach` of `mid` there: a ring whose band lies wholly outside
  // that slab has no point in the region, and its box need not be made (most rings of a long profile).
  const Eigen::Vector3d mid_point = sampler.region().center() - f.o;
  const double mid = mid_point.dot(f.e3), reach = 0.5 * sampler.region().sizes().dot(f.e3.cwiseAbs());
  b.i0 = g.nr;
  b.i1 = -1;
  b.na = g.na;
  for (int i = 0; i < g.nr; ++i) {
    const ProfilePoint &below = g.ring[std::max(0, i - 1)], &above = g.ring[std::min(g.nr - 1, i + 1)], &at = g.ring[i];
    if (std::max({below.z, above.z, at.z}) < mid - reach || std::min({below.z, above.z, at.z}) > mid + reach) continue;
    Eigen::AlignedBox3d box;
    for (const ProfilePoint& p : {below, above, at}) {
      const Eigen::Vector3d c = f.o + p.z * f.e3, e = p.r * span;
      box.extend(c - e);
      box.extend(c + e);
    }
    if (!box.intersects(sampler.region())) continue;
    b.i0 = std::min(b.i0, i);
    b.i1 = i;
  }
}

// cos and sin of phi_of(j) + t dphi, t in [0, 1]: the sample's from the table, turned by t dphi (a few
// degrees: the series is exact to 1e-12; a step coarser than kSmallTurn calls std::cos and std::sin).
void angle_at(const SampleGrid& g, int j, double t, double& c, double& s) {
  const double x = t * g.dphi;
  double cx, sx;
  if (std::abs(x) <= engagement::kSmallTurn) {
    engagement::small_cos_sin(x, cx, sx);
  } else {
    cx = std::cos(x);
    sx = std::sin(x);
  }
  const int k = g.wrap(j);
  c = g.cos_phi[k] * cx - g.sin_phi[k] * sx;
  s = g.sin_phi[k] * cx + g.cos_phi[k] * sx;
}

// The boundary between sample j and j + 1 of ring i (opposite states; f its frame), as an angle.
double refine_angle(const SampleGrid& g, const BlockSamples& b, const Sampler& sampler, const RingFrame& f, int i, int j,
                    int evaluations) {
  const double width = kRefineFraction * g.h / std::max(1e-9, g.ring[i].r * g.dphi);
  // The samples were classified without the facing value of the rear: measure both ends fully.
  auto full = [&](int k) {
    const PointState& s = b.at(i, k);
    const int w = g.wrap(k);
    return std::isnan(s.facing) ? sampler.state(f, g.cos_phi[w], g.sin_phi[w]) : s;
  };
  const double t = engagement::refine_boundary(full(j), full(j + 1), width, evaluations, [&](double u) {
    double c, s;
    angle_at(g, j, u, c, s);
    return sampler.state(f, c, s);
  });
  return g.phi_of(j) + t * g.dphi;
}

// Gaps shorter than the lattice spacing along the ring are below what the stock model resolves
// (classification near a boundary the rays run along): the arcs on both sides are one.
void close_short_gaps(std::vector<std::pair<double, double>>& arcs, double min_gap) {
  size_t m = 0;  // in place: arcs[0..m) are merged
  for (size_t k = 0; k < arcs.size(); ++k) {
    if (m > 0 && arcs[k].first - arcs[m - 1].second < min_gap) arcs[m - 1].second = arcs[k].second;
    else arcs[m++] = arcs[k];
  }
  arcs.resize(m);
  if (arcs.size() > 1 && arcs.front().first + 2.0 * kPi - arcs.back().second < min_gap) {
    arcs.back().second = arcs.front().second + 2.0 * kPi;
    arcs.erase(arcs.begin());
  }
  if (arcs.size() == 1 && arcs.front().second - arcs.front().first >= 2.0 * kPi - min_gap)
    arcs.front() = {0.0, 2.0 * kPi};
}

// The engaged arcs of ring i (f its frame), their ends refined between the samples, into rr (its storage
// reused from block to block).
void ring_arcs(const SampleGrid& g, const BlockSamples& b, int i, const Sampler& sampler, const RingFrame& f,
               int evaluations, RingResult& rr) {
  rr.clear();
  const uint8_t* eng = &b.eng[b.index(i, 0)];
  const int na = g.na;
  auto on = [&](int j) { return eng[j >= na ? j - na : j] != 0; };  // j in [0, 2 na)
  int first_off = -1;
  for (int j = 0; j < na; ++j)
    if (!eng[j]) {
      first_off = j;
      break;
    }
  if (first_off < 0) {  // the full turn
    rr.arcs.push_back({0.0, 2.0 * kPi});
    rr.angle = 2.0 * kPi;
    return;
  }
  // Walk once around from a disengaged sample, so that every arc is seen whole.
  for (int k = 1; k <= na; ++k) {
    const int j = first_off + k;
    if (!on(j) || on(j - 1)) continue;
    int e = j;
    while (on(e + 1)) ++e;
    rr.arcs.push_back(
        {refine_angle(g, b, sampler, f, i, j - 1, evaluations), refine_angle(g, b, sampler, f, i, e, evaluations)});
  }
  close_short_gaps(rr.arcs, g.h / std::max(g.ring[i].r, 1e-9));
  for (const auto& [lo, hi] : rr.arcs) rr.angle += hi - lo;
  engagement::resolved_pieces(rr, g.ring[i].r, g.h);
}

// Marks the samples of ring i (f its frame) whose positions lie in the region (b.eng), in one cheap pass,
// so that only they are classified; returns their count. The frame and the box are copied to locals and
// the tables read through restricted pointers: a store to b.eng could otherwise alias them, and the
// compiler reloaded all eighteen values for every sample instead of vectorising the loop (which it does
// only with AVX2 and above: TF_VECTOR_CLONES). Not inlined: a target clone is called through its resolver.
TF_VECTOR_CLONES int mark_in_region(const SampleGrid& g, const Sampler& sampler, const RingFrame& f, int i, BlockSamples& b) {
  const Eigen::Vector3d& lo = sampler.region().min();
  const Eigen::Vector3d& hi = sampler.region().max();
  const double lx = lo.x(), ly = lo.y(), lz = lo.z(), hx = hi.x(), hy = hi.y(), hz = hi.z();
  const double cx = f.c0.x(), cy = f.c0.y(), cz = f.c0.z();
  const double ax = f.a1.x(), ay = f.a1.y(), az = f.a1.z(), bx = f.a2.x(), by = f.a2.y(), bz = f.a2.z();
  const double* __restrict cos_phi = g.cos_phi.data();
  const double* __restrict sin_phi = g.sin_phi.data();
  uint8_t* __restrict eng = &b.eng[b.index(i, 0)];
  const int na = g.na;
  int n = 0;
  for (int j = 0; j < na; ++j) {
    // The same arithmetic, in the same order, as Sampler::state_in_region's point.
    const double c = cos_phi[j], s = sin_phi[j];
    const double x = cx + c * ax + s * bx, y = cy + c * ay + s * by, z = cz + c * az + s * bz;
    const int in = (x >= lx) & (x <= hx) & (y >= ly) & (y <= hy) & (z >= lz) & (z <= hz);
    eng[j] = static_cast<uint8_t>(in);
    n += in;
  }
  return n;
}

// The samples of ring i (f its frame) that mark_in_region marked, classified; b.eng their states. Returns
// the count engaged.
int classify_ring(const SampleGrid& g, const Sampler& sampler, const RingFrame& f, int i, BlockSamples& b) {
  PointState* state = &b.state[b.index(i, 0)];
  uint8_t* eng = &b.eng[b.index(i, 0)];
  int engaged = 0;
  for (int j = 0; j < g.na; ++j) {
    state[j] = eng[j] ? sampler.state_in_region(f, g.cos_phi[j], g.sin_phi[j]) : PointState{};
    eng[j] = state[j].engaged;
    engaged += eng[j];
  }
  return engaged;
}

// The samples of rings i0..i1 and their arcs; the rings are spread over the threads when there are enough
// of them for each thread to take a few.
void classify_rings(const SampleGrid& g, const Sampler& sampler, int evaluations, BlockSamples& b,
                    std::vector<RingResult>& rings) {
  b.state.resize(size_t(b.i1 - b.i0 + 1) * g.na);
  b.eng.resize(b.state.size());
  b.frame.resize(size_t(b.i1 - b.i0 + 1));
  auto rings_in = [&](const tbb::blocked_range<int>& r) {
    for (int i = r.begin(); i != r.end(); ++i) {
      RingFrame& f = b.frame[size_t(i - b.i0)];
      f = sampler.ring(g.ring[i]);
      // The arcs read only their own ring's samples; a ring with none engaged has none.
      if (mark_in_region(g, sampler, f, i, b) > 0 && classify_ring(g, sampler, f, i, b) > 0)
        ring_arcs(g, b, i, sampler, f, evaluations, rings[i]);
      else
        std::fill_n(&b.state[b.index(i, 0)], g.na, PointState{}), std::fill_n(&b.eng[b.index(i, 0)], g.na, 0);
    }
  };
  b.parallel = b.i1 - b.i0 + 1 >= 2 * kRingGrain;
  const tbb::blocked_range<int> all(b.i0, b.i1 + 1, kRingGrain);
  if (b.parallel) tbb::parallel_for(all, rings_in);
  else rings_in(all);
}

// The extent of each classified ring's arcs, and the area of the profile's ends beyond the first and
// last rings (their rings' engaged fractions of them); their pairs into `out` when kept.
Extent ring_extents(const SampleGrid& g, const BlockSamples& b, const std::vector<RingResult>& rings,
                    const Profile& prof, bool keep_pairs, Engagement& out) {
  Extent x;
  for (int i = b.i0; i <= b.i1; ++i) {
    const RingResult& rr = rings[i];
    if (rr.arcs.empty()) continue;
    if (i == 0) x.area += g.below[i] * rr.angle / (2.0 * kPi);
    if (i == g.nr - 1) x.area += g.above[i] * rr.angle / (2.0 * kPi);
    const double z = g.ring[i].z, r = g.ring[i].r;
    x.zmin = std::min(x.zmin, z);
    x.zmax = std::max(x.zmax, z);
    for (const auto& [lo_a, hi_a] : rr.arcs) {
      double lo, hi;
      cos_range(lo_a, hi_a, lo, hi);
      x.wmin = std::min(x.wmin, r * lo);
      x.wmax = std::max(x.wmax, r * hi);
      if (keep_pairs) {
        const bool full = hi_a - lo_a >= 2.0 * kPi - 1e-12;
        out.pairs.push_back(
            {z, full ? 0.0 : std::fmod(lo_a * kDeg, 360.0), full ? 360.0 : std::fmod(hi_a * kDeg, 360.0)});
      }
    }
    out.max_pairs = std::max(out.max_pairs, static_cast<int>(rr.arcs.size()));
    if (i == 0) x.zmin = std::min(x.zmin, prof.at(0.0).z);
    if (i == g.nr - 1) x.zmax = std::max(x.zmax, prof.at(g.S).z);
  }
  return x;
}

// The smallest arc covering every engaged angle (out.entry_deg, out.exit_deg): the complement of the
// widest gap in their union.
void set_engaged_arc(const std::vector<RingResult>& rings, Engagement& out) {
  std::vector<std::pair<double, double>> all;
  for (const RingResult& rr : rings)
    for (const auto& [a, b] : rr.arcs) {
      if (b - a >= 2.0 * kPi - 1e-12) {
        out.entry_deg = 0.0;
        out.exit_deg = 360.0;
        return;
      }
      const double a0 = engagement::wrap_turn(a), b0 = a0 + (b - a);
      if (b0 > 2.0 * kPi) {
        all.push_back({a0, 2.0 * kPi});
        all.push_back({0.0, b0 - 2.0 * kPi});
      } else {
        all.push_back({a0, b0});
      }
    }
  std::sort(all.begin(), all.end());
  std::vector<std::pair<double, double>> merged;
  for (const auto& iv : all) {
    if (!merged.empty() && iv.first <= merged.back().second + 1e-12)
      merged.back().second = std::max(merged.back().second, iv.second);
    else
      merged.push_back(iv);
  }
  // Gaps between consecutive merged arcs, and the one through 0.
  double best_gap = -1.0, gap_start = 0.0, gap_end = 0.0;
  for (size_t k = 0; k < merged.size(); ++k) {
    const double g0 = merged[k].second;
    const double g1 = k + 1 < merged.size() ? merged[k + 1].first : merged[0].first + 2.0 * kPi;
    if (g1 - g0 > best_gap) {
      best_gap = g1 - g0;
      gap_start = g0;
      gap_end = g1;
    }
  }
  if (best_gap <= 1e-12) {
    out.entry_deg = 0.0;
    out.exit_deg = 360.0;
  } else {
    out.entry_deg = std::fmod(gap_end * kDeg, 360.0);
    out.exit_deg = std::fmod(gap_start * kDeg, 360.0);
    if (out.exit_deg == 0.0 && gap_start > 0.0) out.exit_deg = 360.0;
  }
}

// Engagement of one tool, block after block: the sample grid and its tables are made once per lattice
// spacing, the per-block buffers reused. One block at a time (a lock makes a shared meter safe).
class Meter {
 public:
  Meter(const Tool& tool, const EngagementOptions& options) : profile_(tool), opt_(options) {}

  Engagement measure(const TriDexel& stock, const ToolPose& before, const ToolPose& end,
                     const Eigen::AlignedBox3d* removed) {
    const std::lock_guard<std::mutex> lock(mutex_);
    Engagement out;
    const double h = stock.lattice().h;
    Eigen::AlignedBox3d region;
    if (removed) {
      if (removed->isEmpty()) return out;
      // A sample is classified by rays up to about a spacing away, and the swept parts hold the true
      // tool within the sweep's bound: material the block removed can make a sample engaged up to that far
      // outside the box.
      const double grow = 1.5 * h + opt_.removed_margin_mm;
      region = Eigen::AlignedBox3d(removed->min().array() - grow, removed->max().array() + grow);
    } else {
      const Lattice& L = stock.lattice();
      region = Eigen::AlignedBox3d(L.origin.array() - h, (L.origin + h * Eigen::Vector3d(L.n[0], L.n[1], L.n[2])).array() + h);
    }
    if (!grid_ || grid_->h != h) {
      grid_ = std::make_unique<SampleGrid>(profile_, h, opt_);
      rings_.assign(grid_->nr, {});
      samples_.i0 = 0, samples_.i1 = -1;  // the previous grid's rings are gone
    }
    const SampleGrid& g = *grid_;
    const Sampler sampler(stock, before, end, region);
    for (int i = samples_.i0; i <= samples_.i1; ++i) rings_[i].clear();  // the previous block's
    active_rings(g, sampler, samples_);
    if (samples_.i1 < samples_.i0) return out;
    const int evaluations = std::max(1, opt_.refine_steps);
    classify_rings(g, sampler, evaluations, samples_, rings_);
    Extent x = ring_extents(g, samples_, rings_, profile_, opt_.keep_pairs, out);
    if (!std::isfinite(x.zmin)) return out;  // no ring engaged
    engagement::add_pair_areas(g, samples_, rings_, sampler, profile_, evaluations, strips_, x);
    out.area_mm2 = std::max(0.0, x.area);
    out.axial_depth_mm = x.zmax - x.zmin;
    out.radial_width_mm = x.wmax - x.wmin;
    set_engaged_arc(rings_, out);
    return out;
  }

 private:
  Profile profile_;
  EngagementOptions opt_;
  std::mutex mutex_;
  std::unique_ptr<SampleGrid> grid_;
  BlockSamples samples_;
  std::vector<RingResult> rings_;
  std::vector<Extent> strips_;
};

}  // namespace

bool stock_contains(const TriDexel& stock, const Eigen::Vector3d& p) {
  return engagement::material_depth(stock, p) <= 0.0;
}

Engagement measure_engagement(const TriDexel& stock, const Tool& tool, const ToolPose& before, const ToolPose& end,
                              const EngagementOptions& opt, const Eigen::AlignedBox3d* removed) {
  return Meter(tool, opt).measure(stock, before, end, removed);
}

EngagementProbe engagement_probe(const EngagementOptions& options) {
  // One meter per cutting form met (a program's tools), found by the form's values, not its address.
  struct Meters {
    std::mutex mutex;
    std::vector<std::pair<std::array<double, 4>, std::unique_ptr<Meter>>> by_form;
    Meter& of(const Tool& tool, const EngagementOptions& opt) {
      const double corner = std::holds_alternative<BullCutter>(tool.cutter) ? std::get<BullCutter>(tool.cutter).corner_radius : -1.0;
      const std::array<double, 4> key{double(tool.cutter.index()), tool.radius(), corner, tool.flute_length};
      const std::lock_guard<std::mutex> lock(mutex);
      for (auto& [k, m] : by_form)
        if (k == key) return *m;
      by_form.emplace_back(key, std::make_unique<Meter>(tool, opt));
      return *by_form.back().second;
    }
  };
  auto meters = std::make_shared<Meters>();
  return [meters, options](const Tool& tool, const TriDexel& stock, const ToolPose& before, const ToolPose& end,
                           const Eigen::AlignedBox3d& removed) {
    return meters->of(tool, options).measure(stock, before, end, &removed);
  };
}

}  // namespace tf
