// The engaged area between the rings of a block (rings.hpp): integrated along the profile where
// neighbouring rings hold the same pieces of the engaged region, by meridian strips where they do not.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "rings.hpp"

namespace tf::engagement {

void cos_range(double a, double b, double& lo, double& hi) {
  const double ca = std::cos(a), cb = std::cos(b);  // once each: cos may set errno, so it is not merged
  lo = std::min(ca, cb);
  hi = std::max(ca, cb);
  const double k0 = std::ceil(a / kPi), k1 = std::floor(b / kPi);
  for (double k = k0; k <= k1; ++k) {
    if (static_cast<long long>(std::abs(k)) % 2 == 0) hi = 1.0;
    else lo = -1.0;
  }
}

void resolved_pieces(RingResult& rr, double r, double h) {
  rr.pieces.clear();
  const double join = 2.0 * h / std::max(r, 1e-9), least = h / std::max(r, 1e-9);
  for (const auto& arc : rr.arcs) {
    if (!rr.pieces.empty() && arc.first - rr.pieces.back().second < join) rr.pieces.back().second = arc.second;
    else rr.pieces.push_back(arc);
  }
  if (rr.pieces.size() > 1 && rr.pieces.front().first + 2.0 * kPi - rr.pieces.back().second < join) {
    rr.pieces.back().second = rr.pieces.front().second + 2.0 * kPi;
    rr.pieces.erase(rr.pieces.begin());
  }
  std::erase_if(rr.pieces, [&](const std::pair<double, double>& p) { return p.second - p.first < least; });
}

namespace {

// f(j), in increasing j < na, for every angle whose engaged flag differs between two rings' flags (0 or
// 1; a null ring reads as all 0). Eight angles are compared at once: a ring pair changes state at a few
// angles of sixty, and comparing them one by one was a sixth of the strips' cost on the raster.
template <class F>
void for_each_change(const uint8_t* below, const uint8_t* above, int na, F&& f) {
  int j = 0;
  if constexpr (std::endian::native == std::endian::little) {
    for (; j + 8 <= na; j += 8) {
      uint64_t x = 0, y = 0;
      if (below) std::memcpy(&x, below + j, 8);
      if (above) std::memcpy(&y, above + j, 8);
      for (uint64_t diff = x ^ y; diff != 0; diff &= diff - 1) f(j + std::countr_zero(diff) / 8);
    }
  }
  for (; j < na; ++j)
    if ((below ? below[j] : 0) != (above ? above[j] : 0)) f(j);
}

// f(x0, x1) for each part [x0, x1] of the cell [c0, c1] (c0 within a step of [0, 2 pi), c1 - c0 below a
// turn) that one of a ring's engaged arcs covers.
template <class F>
void for_each_covered(const RingResult& rr, double c0, double c1, F&& f) {
  for (const auto& [lo, hi] : rr.arcs) {
    const double a0 = wrap_turn(lo), a1 = a0 + (hi - lo);
    for (int m = -1; m <= 1; ++m) {
      const double x0 = std::max(a0 + 2.0 * kPi * m, c0), x1 = std::min(a1 + 2.0 * kPi * m, c1);
      if (x0 < x1) f(x0, x1);
    }
  }
}

// The angle (radians) that a ring's engaged arcs cover of the cell [c0, c1].
double cell_cover(const RingResult& rr, double c0, double c1) {
  double cover = 0.0;
  for_each_covered(rr, c0, c1, [&](double x0, double x1) { cover += x1 - x0; });
  return cover;
}

// The extent of cos over the part of the cell [c0, c1] that a ring's engaged arcs cover, into lo and hi
// (unchanged where they cover none of it).
void covered_cos_range(const RingResult& rr, double c0, double c1, double& lo, double& hi) {
  for_each_covered(rr, c0, c1, [&](double x0, double x1) {
    double l, h;
    cos_range(x0, x1, l, h);
    lo = std::min(lo, l), hi = std::max(hi, h);
  });
}

// Where the state changes between ring i and ring i + 1 along a sample's meridian, the bands are off by
// the strip between the band edge and the refined boundary: the strips' area, and the boundaries, into x.
void meridian_strips(const SampleGrid& g, const BlockSamples& b, const std::vector<RingResult>& rings,
                     const Sampler& sampler, const Profile& prof, int evaluations, int i, Extent& x) {
  const double width = kRefineFraction * g.h / g.ds;
  const uint8_t* below = i >= b.i0 ? &b.eng[b.index(i, 0)] : nullptr;
  const uint8_t* above = i + 1 <= b.i1 ? &b.eng[b.index(i + 1, 0)] : nullptr;
  for_each_change(below, above, g.na, [&](int j) {
    const bool a = below && below[j] != 0;
    double s0 = g.s_of(i), s1 = g.s_of(i + 1);
    const Sampler::Column col = sampler.column(g.cos_phi[j], g.sin_phi[j]);
    // Profile points between the rings: from ring i's by the series where the corner turns little.
    const ProfilePoint& base = g.ring[size_t(i)];
    const double s_base = g.s_of(i);
    auto at = [&](double s) { return sampler.state(col, prof.at(s, &base, s_base)); };
    // A ring outside i0..i1 was not classified, and the rear's facing value was not measured: measure.
    auto end = [&](int k) {
      const PointState s = k >= b.i0 && k <= b.i1 ? b.at(k, j) : PointState{};
      return std::isnan(s.facing) && (k >= b.i0 && k <= b.i1) ? sampler.state(col, g.ring[k]) : s;
    };
    PointState sa = end(i), sc = end(i + 1);
    double sb = -1.0;
    // The measures are not smooth across a joint of the profile: the state there bounds the bracket, and
    // where the normal jumps (a flat end's rim) a change of state across it is at the rim.
    for (const Profile::Joint& jt : prof.joints()) {
      if (!(jt.s > s0 && jt.s < s1)) continue;
      const double eps = jt.jump ? 1e-9 * g.S : 0.0;
      const PointState under = at(jt.s - eps), over = jt.jump ? at(jt.s + eps) : under;
      if (under.engaged != over.engaged) {
        sb = jt.s;
        break;
      }
      if (under.engaged == sa.engaged) s0 = jt.s + eps, sa = over;
      else s1 = jt.s - eps, sc = under;
    }
    if (sb < 0.0)
      sb = s0 + (s1 - s0) * engagement::refine_boundary(sa, sc, width * g.ds / (s1 - s0), evaluations,
                                                        [&](double u) { return at(s0 + u * (s1 - s0)); });
    const double edge = (i + 1) * g.ds;  // band edge between the rings
    // The rings' fractions gave the engaged angle of ring i below the edge and of ring i + 1 above it: in
    // the column's cell, the angle ring i covers beyond ring i + 1 should end at sb, not at the edge
    // (engaged below, sb above the edge: more area), and the angle ring i + 1 covers beyond ring i start
    // there. Weighting the strip by the arcs' cover of the cell, not the whole cell, keeps an arc narrower
    // than a cell from moving a cell's worth of area.
    const double cell0 = g.phi_of(j) - 0.5 * g.dphi, cell1 = cell0 + g.dphi;
    const double gained = cell_cover(rings[size_t(i)], cell0, cell1) - cell_cover(rings[size_t(i + 1)], cell0, cell1);
    const double strip = prof.band_area(std::min(sb, edge), std::max(sb, edge), &base, s_base) / (2.0 * kPi);
    x.area += gained * (sb > edge ? strip : -strip);
    const ProfilePoint p = prof.at(sb, &base, s_base);
    x.zmin = std::min(x.zmin, p.z);
    x.zmax = std::max(x.zmax, p.z);
    // The boundary point reaches across the cell as far as the engaged ring's arcs do there (the sample's
    // own angle alone would shorten a slot's width by cos(dphi / 2), its ends lying between samples).
    double lo = g.cos_phi[j], hi = lo;
    covered_cos_range(rings[size_t(a ? i : i + 1)], cell0, cell1, lo, hi);
    x.wmin = std::min(x.wmin, p.r * lo);
    x.wmax = std::max(x.wmax, p.r * hi);
  });
}

bool full_turn(const RingResult& rr) { return rr.angle >= 2.0 * kPi - 1e-12; }

// Whether two arcs (radians, entry < exit, less than a turn) overlap somewhere around the circle.
bool arcs_overlap(const std::pair<double, double>& p, const std::pair<double, double>& q) {
  const double p0 = wrap_turn(p.first), p1 = p0 + (p.second - p.first);
  const double q0 = wrap_turn(q.first), q1 = q0 + (q.second - q.first);
  for (int m = -1; m <= 1; ++m)
    if (p0 < q1 + 2.0 * kPi * m && q0 + 2.0 * kPi * m < p1) return true;
  return false;
}

// Whether piece q is piece p's partner on the neighbouring ring: overlapping, and neither end turned by
// more than max_move (radians). An end that moves farther between two rings follows a boundary running around
// the tool rather than along it (a step of the stock facing the axis): the engaged angle may jump there,
// between the rings, and no polynomial through the rings' fractions would see where.
bool partner(const std::pair<double, double>& p, const std::pair<double, double>& q, double max_move) {
  return arcs_overlap(p, q) && std::abs(remainder_turn(p.first - q.first)) <= max_move &&
         std::abs(remainder_turn(p.second - q.second)) <= max_move;
}

// Whether the engaged arcs of two neighbouring rings are the same pieces of the engaged region, as far as
// the lattice resolves them: as many, in the same order around the tool, each its partner's (or both rings
// engaged all round, or neither engaged). Between such rings each piece is bounded by its arcs' ends joined
// across, so its engaged angle is smooth in the arc length along the profile; an arc or a gap below the
// lattice spacing (classification noise near a boundary the rays run along) does not make them differ.
bool same_pieces(const RingResult& a, const RingResult& b, double max_move) {
  if (a.arcs.empty() || b.arcs.empty()) return a.arcs.empty() && b.arcs.empty();
  if (full_turn(a) || full_turn(b)) return full_turn(a) && full_turn(b);
  const size_t k = a.pieces.size();
  if (k != b.pieces.size() || k == 0) return false;
  for (size_t shift = 0; shift < k; ++shift) {
    bool all = true;
    for (size_t j = 0; j < k && all; ++j) all = partner(a.pieces[j], b.pieces[(j + shift) % k], max_move);
    if (all) return true;
  }
  return false;
}

// The engaged area between rings i and i + 1, and the boundaries found there, into x. Where both rings
// hold the same pieces of the engaged region and no joint of the profile lies between them, the engaged
// fraction of the turn is smooth in the arc length along the profile: it is integrated as the polynomial
// through these rings and those neighbours that hold the same pieces too (cubic with both, quadratic with
// one, linear with none), with no further evaluation. Elsewhere (a piece starts, ends, splits or joins
// between the rings, or the profile bends at a joint) each ring's fraction covers its half of the band
// and the meridian strips move its edge to the refined boundary of every column whose state changes.
void pair_area(const SampleGrid& g, const BlockSamples& b, const std::vector<RingResult>& rings,
               const Sampler& sampler, const Profile& prof, int evaluations, int i, Extent& x) {
  auto f = [&](int k) { return rings[size_t(k)].angle / (2.0 * kPi); };
  auto smooth = [&](int k) {  // pair k holds the same pieces, unbent by a joint
    return k >= 0 && k + 1 < g.nr && !g.joint[size_t(k)] &&
           same_pieces(rings[size_t(k)], rings[size_t(k + 1)],
                       kSmoothEndMove * g.ds / std::max({g.ring[size_t(k)].r, g.ring[size_t(k + 1)].r, 1e-9}));
  };
  if (smooth(i)) {
    const SampleGrid::PairWeights& w = g.weights[size_t(i)];
    const bool left = smooth(i - 1), right = smooth(i + 1);
    if (left && right) x.area += w.cubic[0] * f(i - 1) + w.cubic[1] * f(i) + w.cubic[2] * f(i + 1) + w.cubic[3] * f(i + 2);
    else if (left) x.area += w.left[0] * f(i - 1) + w.left[1] * f(i) + w.left[2] * f(i + 1);
    else if (right) x.area += w.right[0] * f(i) + w.right[1] * f(i + 1) + w.right[2] * f(i + 2);
    else x.area += w.linear[0] * f(i) + w.linear[1] * f(i + 1);
    return;
  }
  x.area += f(i) * g.above[size_t(i)] + f(i + 1) * g.below[size_t(i + 1)];
  meridian_strips(g, b, rings, sampler, prof, evaluations, i, x);
}

}  // namespace

void add_pair_areas(const SampleGrid& g, const BlockSamples& b, const std::vector<RingResult>& rings,
                    const Sampler& sampler, const Profile& prof, int evaluations, std::vector<Extent>& parts,
                    Extent& x) {
  const int first = std::max(0, b.i0 - 1), last = std::min(b.i1, g.nr - 2);
  if (last < first) return;
  parts.assign(size_t(last - first + 1), Extent{});
  auto pairs_in = [&](const tbb::blocked_range<int>& r) {
    for (int i = r.begin(); i != r.end(); ++i)
      pair_area(g, b, rings, sampler, prof, evaluations, i, parts[size_t(i - first)]);
  };
  const tbb::blocked_range<int> all(first, last + 1, kRingGrain);
  if (b.parallel) tbb::parallel_for(all, pairs_in);
  else pairs_in(all);
  for (const Extent& p : parts) x.add(p);
}

}  // namespace tf::engagement
