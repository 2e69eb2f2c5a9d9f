// Cutter-workpiece engagement at a block's end by sampling the cutting surface against the in-process
// tri-dexel stock (include/tiltfield/engagement/engagement.hpp has the method and the angle convention).
#include "tiltfield/engagement/engagement.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

namespace tf {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = 180.0 / kPi;
// How deep inside the tool a surface point's material test looks (mm): a block that only grazes a surface
// cut before (a repeated pass) engages nothing.
constexpr double kInside = 1e-3;

// Signed along-ray distance from coordinate t to the nearest material boundary of a ray: negative
// inside material, positive outside, +inf for an empty ray.
double along_ray_distance(const Dexel& ray, float t) {
  // The intervals are sorted and disjoint: the first one ending at or after t, and the one before it.
  const Interval* b = ray.begin();
  const Interval* e = ray.end();
  const Interval* it = std::lower_bound(b, e, t, [](const Interval& iv, float x) { return iv.hi < x; });
  if (it != e && t >= it->lo) return -std::min(t - it->lo, it->hi - t);
  double best = std::numeric_limits<double>::infinity();
  if (it != e) best = it->lo - t;
  if (it != b) best = std::min<double>(best, t - (it - 1)->hi);
  return best;
}

// The cutting surface of a body of revolution as a meridian profile, by arc length s from the tip's
// centre: radius r(s), height z(s) and the outward normal's radial and axial components.
struct ProfilePoint {
  double r, z, nr, nz;
};

class Profile {
 public:
  explicit Profile(const Tool& tool) : top_(tool.flute_length), R_(tool.radius()) {
    if (const auto* b = std::get_if<BullCutter>(&tool.cutter)) {
      rc_ = b->corner_radius;
    } else if (std::holds_alternative<BallCutter>(tool.cutter)) {
      rc_ = R_;
    }
    flat_ = R_ - rc_;
    arc_ = 0.5 * kPi * rc_;
    length_ = flat_ + arc_ + std::max(0.0, top_ - rc_);
  }
  double length() const { return length_; }
  ProfilePoint at(double s) const {
    s = std::clamp(s, 0.0, length_);
    if (s < flat_) return {s, 0.0, 0.0, -1.0};  // end face (flat and bull)
    if (s < flat_ + arc_) {                     // ball or torus corner, angle from the tip's normal
      const double th = (s - flat_) / rc_;
      return {flat_ + rc_ * std::sin(th), rc_ - rc_ * std::cos(th), std::sin(th), -std::cos(th)};
    }
    return {R_, rc_ + (s - flat_ - arc_), 1.0, 0.0};  // flutes
  }
  // Area of the band [s0, s1] over the full turn, exact for each piece of the profile, mm^2.
  double band_area(double s0, double s1) const {
    double a = 0.0;
    auto piece = [&](double lo, double hi, auto&& antiderivative) {
      const double x0 = std::clamp(s0, lo, hi), x1 = std::clamp(s1, lo, hi);
      if (x1 > x0) a += antiderivative(x1) - antiderivative(x0);
    };
    piece(0.0, flat_, [](double s) { return kPi * s * s; });
    piece(flat_, flat_ + arc_, [&](double s) {
      const double th = (s - flat_) / rc_;
      return 2.0 * kPi * rc_ * (flat_ * th - rc_ * std::cos(th));
    });
    piece(flat_ + arc_, length_, [&](double s) { return 2.0 * kPi * R_ * s; });
    return a;
  }

 private:
  double top_, R_, rc_ = 0.0, flat_ = 0.0, arc_ = 0.0, length_ = 0.0;
};

// Rigid motion of the tool frame (tip at the origin, axis e3) to a pose, with the frame's e1 carried by
// the minimal rotation from a reference so that `before` and `end` frames agree about the axis' roll.
struct Frame {
  Eigen::Vector3d o, e1, e2, e3;
  Eigen::Vector3d point(double r, double z, double c, double s) const { return o + r * (c * e1 + s * e2) + z * e3; }
  Eigen::Vector3d dir(double nr, double nz, double c, double s) const { return nr * (c * e1 + s * e2) + nz * e3; }
};

Frame frame_at(const ToolPose& pose, const Eigen::Vector3d& e1_hint) {
  Frame f;
  f.o = pose.tip;
  f.e3 = pose.axis.normalized();
  Eigen::Vector3d e1 = e1_hint - e1_hint.dot(f.e3) * f.e3;
  if (e1.norm() < 1e-9) e1 = f.e3.unitOrthogonal();
  f.e1 = e1.normalized();
  f.e2 = f.e1.cross(f.e3);  // (n, f, a) is left-handed: angles run clockwise seen from the spindle
  return f;
}

// Largest and smallest of cos over the arc [a, b] (radians, b >= a, b - a <= 2 pi).
void cos_range(double a, double b, double& lo, double& hi) {
  lo = std::min(std::cos(a), std::cos(b));
  hi = std::max(std::cos(a), std::cos(b));
  const double k0 = std::ceil(a / kPi), k1 = std::floor(b / kPi);
  for (double k = k0; k <= k1; ++k) {
    if (std::fmod(std::abs(k), 2.0) == 0.0) hi = 1.0;
    else lo = -1.0;
  }
}

class Sampler {
 public:
  Sampler(const TriDexel& stock, const Tool& tool, const ToolPose& before, const ToolPose& end)
      : stock_(stock), profile_(tool) {
    const Eigen::Vector3d a = end.axis.normalized();
    Eigen::Vector3d f = (end.tip - before.tip) - (end.tip - before.tip).dot(a) * a;
    if (f.norm() < 1e-9 * std::max(1.0, (end.tip - before.tip).norm())) {
      f = Eigen::Vector3d::UnitX() - a.x() * a;
      if (f.norm() < 1e-6) f = Eigen::Vector3d::UnitY() - a.y() * a;
    }
    f.normalize();
    // Angle phi: direction cos(phi) n + sin(phi) f with n = a x f; the frame's e1 = n, e2 = f gives
    // point(r, z, cos phi, sin phi).
    const Eigen::Vector3d n = a.cross(f);
    end_ = frame_at(end, n);
    // The same material frame earlier: the minimal rotation taking the end axis to the earlier one.
    auto carried = [&](const ToolPose& p) {
      const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(a, p.axis.normalized());
      return frame_at(p, q * n);
    };
    before_ = carried(before);
  }

  const Profile& profile() const { return profile_; }

  bool engaged(double s, double phi) const { return engaged(profile_.at(s), std::cos(phi), std::sin(phi)); }

  // The same at a profile point and the angle's cosine and sine (the sampling grid precomputes both).
  bool engaged(const ProfilePoint& pp, double c, double sn) const {
    const Eigen::Vector3d x = end_.point(pp.r, pp.z, c, sn);
    const Eigen::Vector3d v = x - before_.point(pp.r, pp.z, c, sn);
    const double vn = v.norm();
    if (!(vn > 1e-12)) return false;
    const Eigen::Vector3d nu = end_.dir(pp.nr, pp.nz, c, sn);
    if (nu.dot(v) <= 1e-6 * vn) return false;  // faces away from its motion
    // Material an epsilon inside the tool, before this block: the block removes it at its end.
    return stock_contains(stock_, x - kInside * nu);
  }

  double height(double s) const { return profile_.at(s).z; }
  double radius(double s) const { return profile_.at(s).r; }

 private:
  const TriDexel& stock_;
  Profile profile_;
  Frame end_, before_;
};

// Bisection between a and b (states sa at a, the opposite at b) of a one-parameter test; the boundary.
template <class Test>
double refine(double a, double b, bool sa, int steps, const Test& test) {
  for (int i = 0; i < steps; ++i) {
    const double m = 0.5 * (a + b);
    if (test(m) == sa) a = m;
    else b = m;
  }
  return 0.5 * (a + b);
}

// Per ring: the engaged arcs (radians, entry < exit, exit may pass 2 pi) found around the ring.
struct RingResult {
  std::vector<std::pair<double, double>> arcs;
  double angle = 0.0;  // engaged radians in total
};

// The sample grid on the cutting surface: nr rings at the middle of equal bands of the profile (arc length
// s_of(i)), na angles phi_of(j) around each, and per sample whether it is engaged.
struct SampleGrid {
  SampleGrid(const Profile& prof, double h, const EngagementOptions& opt) : S(prof.length()) {
    const double ds_want = opt.axial_step_mm > 0 ? opt.axial_step_mm : h;
    nr = std::clamp(static_cast<int>(std::ceil(S / ds_want)), 1, std::max(1, opt.max_rings));
    ds = S / nr;
    na = std::max(8, static_cast<int>(std::lround(360.0 / std::max(0.01, opt.angle_step_deg))));
    dphi = 2.0 * kPi / na;
    state.resize(size_t(nr) * na);
  }
  double s_of(int i) const { return (i + 0.5) * ds; }
  double phi_of(int j) const { return (j + 0.5) * dphi; }
  // Sample j of ring i, j taken around the ring.
  bool st(int i, int j) const { return state[size_t(i) * na + ((j % na) + na) % na] != 0; }

  double S;  // the profile's length, mm
  int nr = 0, na = 0;
  double ds = 0.0, dphi = 0.0;
  std::vector<uint8_t> state;
};

// Classifies every sample of the grid as engaged or not. A ring whose band `cull` finds free of material
// stays disengaged without a test.
void classify_samples(SampleGrid& g, const Sampler& sampler, const ToolPose& end, const MaterialCull& cull) {
  std::vector<double> cos_phi(g.na), sin_phi(g.na);
  for (int j = 0; j < g.na; ++j) {
    cos_phi[j] = std::cos(g.phi_of(j));
    sin_phi[j] = std::sin(g.phi_of(j));
  }
  const Eigen::Vector3d axis = end.axis.normalized();
  // A circle of radius r about axis a spans r sqrt(1 - a_k^2) along axis k.
  const Eigen::Vector3d span = (Eigen::Vector3d::Ones() - axis.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt();
  tbb::parallel_for(0, g.nr, [&](int i) {
    if (cull) {
      // The band of ring i (to the neighbouring rings, which its refinement may reach).
      Eigen::AlignedBox3d box;
      for (const double s : {std::max(0.0, g.s_of(i - 1)), std::min(g.S, g.s_of(i + 1))}) {
        const Eigen::Vector3d c = end.tip + sampler.height(s) * axis, e = sampler.radius(s) * span;
        box.extend(c - e);
        box.extend(c + e);
      }
      if (!cull(box)) return;  // state stays 0
    }
    const ProfilePoint pp = sampler.profile().at(g.s_of(i));
    for (int j = 0; j < g.na; ++j) g.state[size_t(i) * g.na + j] = sampler.engaged(pp, cos_phi[j], sin_phi[j]);
  });
}

// Gaps shorter than the lattice spacing along the ring are below what the stock model resolves
// (classification near a boundary the rays run along): the arcs on both sides are one.
void close_short_gaps(std::vector<std::pair<double, double>>& arcs, double min_gap) {
  std::vector<std::pair<double, double>> merged;
  for (const auto& arc : arcs) {
    if (!merged.empty() && arc.first - merged.back().second < min_gap) merged.back().second = arc.second;
    else merged.push_back(arc);
  }
  if (merged.size() > 1 && merged.front().first + 2.0 * kPi - merged.back().second < min_gap) {
    merged.back().second = merged.front().second + 2.0 * kPi;
    merged.erase(merged.begin());
  }
  if (merged.size() == 1 && merged.front().second - merged.front().first >= 2.0 * kPi - min_gap)
    merged.front() = {0.0, 2.0 * kPi};
  arcs = std::move(merged);
}

// The engaged arcs of ring i, their ends refined between the samples.
RingResult ring_arcs(const SampleGrid& g, int i, const Sampler& sampler, double h, int refine_steps) {
  RingResult rr;
  int first_off = -1;
  for (int j = 0; j < g.na; ++j)
    if (!g.st(i, j)) {
      first_off = j;
      break;
    }
  if (first_off < 0) {  // the full turn
    rr.arcs.push_back({0.0, 2.0 * kPi});
    rr.angle = 2.0 * kPi;
    return rr;
  }
  const double s = g.s_of(i);
  auto test = [&](double phi) { return sampler.engaged(s, phi); };
  // Walk once around from a disengaged sample, so that every arc is seen whole.
  for (int k = 1; k <= g.na; ++k) {
    const int j = first_off + k;
    if (!g.st(i, j) || g.st(i, j - 1)) continue;
    int e = j;
    while (g.st(i, e + 1)) ++e;
    const double entry = refine(g.phi_of(j - 1), g.phi_of(j - 1) + g.dphi, false, refine_steps, test);
    const double exit = refine(g.phi_of(e), g.phi_of(e) + g.dphi, true, refine_steps, test);
    rr.arcs.push_back({entry, exit});
  }
  close_short_gaps(rr.arcs, h / std::max(sampler.radius(s), 1e-9));
  for (const auto& [a, b] : rr.arcs) rr.angle += b - a;
  return rr;
}

// The engaged area (mm^2) and the extent of the engaged surface: its heights z along the axis and its
// offsets w along n.
struct Extent {
  double area = 0.0;
  double zmin = std::numeric_limits<double>::infinity(), zmax = -zmin;
  double wmin = zmin, wmax = -zmin;
};

// Each ring's band times its engaged fraction, and the extent of its arcs; their pairs into `out` when kept.
Extent ring_bands(const SampleGrid& g, const std::vector<RingResult>& rings, const Sampler& sampler, bool keep_pairs,
                  Engagement& out) {
  Extent x;
  for (int i = 0; i < g.nr; ++i) {
    const RingResult& rr = rings[i];
    if (rr.arcs.empty()) continue;
    x.area += sampler.profile().band_area(i * g.ds, (i + 1) * g.ds) * rr.angle / (2.0 * kPi);
    const double z = sampler.height(g.s_of(i)), r = sampler.radius(g.s_of(i));
    x.zmin = std::min(x.zmin, z);
    x.zmax = std::max(x.zmax, z);
    for (const auto& [a, b] : rr.arcs) {
      double lo, hi;
      cos_range(a, b, lo, hi);
      x.wmin = std::min(x.wmin, r * lo);
      x.wmax = std::max(x.wmax, r * hi);
      if (keep_pairs) {
        const bool full = b - a >= 2.0 * kPi - 1e-12;
        out.pairs.push_back({z, full ? 0.0 : std::fmod(a * kDeg, 360.0), full ? 360.0 : std::fmod(b * kDeg, 360.0)});
      }
    }
    out.max_pairs = std::max(out.max_pairs, static_cast<int>(rr.arcs.size()));
    if (i == 0) x.zmin = std::min(x.zmin, sampler.height(0.0));
    if (i == g.nr - 1) x.zmax = std::max(x.zmax, sampler.height(g.S));
  }
  return x;
}

// Where the state changes between rings along a sample's meridian, the bands are off by the strip between
// the band edge and the refined boundary: the strip's area, and the boundary into the extent.
void add_meridian_strips(const SampleGrid& g, const Sampler& sampler, int refine_steps, Extent& x) {
  for (int j = 0; j < g.na; ++j) {
    const double phi = g.phi_of(j);
    auto test = [&](double s) { return sampler.engaged(s, phi); };
    for (int i = 0; i + 1 < g.nr; ++i) {
      const bool a = g.st(i, j), b = g.st(i + 1, j);
      if (a == b) continue;
      const double sb = refine(g.s_of(i), g.s_of(i + 1), a, refine_steps, test);
      const double edge = (i + 1) * g.ds;  // band edge between the rings
      // Engaged below (a): the engaged band should end at sb, not at the edge; engaged above: start at sb.
      const double lo = std::min(sb, edge), hi = std::max(sb, edge);
      const double strip = sampler.profile().band_area(lo, hi) / g.na;
      x.area += (a ? 1.0 : -1.0) * (sb > edge ? strip : -strip);
      const double z = sampler.height(sb), r = sampler.radius(sb);
      x.zmin = std::min(x.zmin, z);
      x.zmax = std::max(x.zmax, z);
      x.wmin = std::min(x.wmin, r * std::cos(phi));
      x.wmax = std::max(x.wmax, r * std::cos(phi));
    }
  }
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
      const double a0 = std::fmod(a, 2.0 * kPi), b0 = a0 + (b - a);
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

}  // namespace

bool stock_contains(const TriDexel& stock, const Eigen::Vector3d& p) {
  const Lattice& L = stock.lattice();
  const double inv_h = 1.0 / L.h;
  double best = std::numeric_limits<double>::infinity();
  bool inside = false;
  for (int d = 0; d < 3; ++d) {
    const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
    // The nearest ray; the range test comes first so that the conversion to int cannot overflow.
    const double fu = (p[u] - L.origin[u]) * inv_h + 0.5, fv = (p[v] - L.origin[v]) * inv_h + 0.5;
    if (!(fu >= 0.0 && fv >= 0.0 && fu < L.n[u] && fv < L.n[v])) return false;  // outside the lattice: no material
    const int iu = static_cast<int>(fu), iv = static_cast<int>(fv);
    const double sd = along_ray_distance(stock.ray(d, iu, iv), static_cast<float>(p[d] - L.origin[d]));
    if (std::abs(sd) < best) {
      best = std::abs(sd);
      inside = sd <= 0.0;
    }
  }
  return inside;
}

Engagement measure_engagement(const TriDexel& stock, const Tool& tool, const ToolPose& before, const ToolPose& end,
                              const EngagementOptions& opt, const MaterialCull& cull) {
  Engagement out;
  const Sampler sampler(stock, tool, before, end);
  const double h = stock.lattice().h;
  SampleGrid grid(sampler.profile(), h, opt);
  classify_samples(grid, sampler, end, cull);
  std::vector<RingResult> rings(grid.nr);
  tbb::parallel_for(0, grid.nr, [&](int i) { rings[i] = ring_arcs(grid, i, sampler, h, opt.refine_steps); });
  Extent x = ring_bands(grid, rings, sampler, opt.keep_pairs, out);
  if (!(x.area > 0.0)) return out;
  add_meridian_strips(grid, sampler, opt.refine_steps, x);
  out.area_mm2 = std::max(0.0, x.area);
  out.axial_depth_mm = x.zmax - x.zmin;
  out.radial_width_mm = x.wmax - x.wmin;
  set_engaged_arc(rings, out);
  return out;
}

EngagementProbe engagement_probe(const EngagementOptions& options) {
  return [options](const Tool& tool, const TriDexel& stock, const ToolPose& before, const ToolPose& end,
                   const MaterialCull& cull) { return measure_engagement(stock, tool, before, end, options, cull); };
}

}  // namespace tf
