// Shank and holder collisions in time order. The cut of a block takes the union of its cutting parts'
// sweeps out of the material, and a shank or holder collides with what is left; but a shank that gets to
// material before the flutes do (a feed up the tool's axis under an overhang) crashes into material the
// union has already taken away. The rays where that can have happened (Accum::masked) are decided here,
// slice by slice of the block: the shank swept over a slice against the material the cutting parts have
// left at the slice's end.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "simulator.hpp"

namespace tf::sim {

namespace {

// Slices of a block in the time-ordered check: each moves the tool's non-cutting parts by at most this
// much (mm), with at most kMaxSlices of them.
constexpr double kSliceMotion = 1.0;
constexpr int kMaxSlices = 64;
constexpr int kProbes = 32;  // poses sampled for the motion of the block

// Whether a non-cutting part can reach material before the cutting parts in this block: not when the
// axis keeps its direction and the tip never moves along it toward the shank. Then every point
// rises along the tool, relative to it, from the cutting parts' heights to the shank's and the holder's (all
// stacked above the flutes) or keeps its height, so where both meet it the cutting parts come first.
bool shank_can_lead(const PoseAt& pose_at) {
  ToolPose prev = pose_at(0.0);
  const Eigen::Vector3d a = prev.axis.normalized();
  for (int i = 1; i <= kProbes; ++i) {
    const ToolPose p = pose_at(double(i) / kProbes);
    if ((p.axis.normalized() - a).norm() > 1e-9) return true;
    if ((p.tip - prev.tip).dot(a) > 1e-9) return true;
    prev = p;
  }
  return false;
}

// The path length of the top of the non-cutting parts (`top` mm up the axis from the tip) and of the tip,
// whichever is longer, from kProbes poses.
double top_motion(const PoseAt& pose_at, double top) {
  double tip_path = 0.0, top_path = 0.0;
  ToolPose prev = pose_at(0.0);
  for (int i = 1; i <= kProbes; ++i) {
    const ToolPose p = pose_at(double(i) / kProbes);
    tip_path += (p.tip - prev.tip).norm();
    top_path += (p.tip + top * p.axis.normalized() - prev.tip - top * prev.axis.normalized()).norm();
    prev = p;
  }
  return std::max(tip_path, top_path);
}

}  // namespace

// For every masked ray and slice [t_k, t_k+1] of the block: the cutting parts swept from the start to
// t_k+1 are taken out of the ray's material before the block, and each non-cutting part swept over the
// slice is measured against what is left, into depth (the longest overlap per grid and component, as the
// cut records it). Material left at a slice's end was there all through the slice, so a reported overlap
// is one the part really passed through; a part reaching material less than a slice's motion before the
// cutting parts take it away is not reported.
void Simulator::add_ordered_depths(const Block& b, const PoseAt& pose_at, double turn, Depths& depth) const {
  size_t rays = 0;
  for (const Accum& a : accum_) rays += a.masked.size();
  if (rays == 0 || !shank_can_lead(pose_at)) return;
  const std::vector<ToolPart>& parts = tools_.parts(b.tool);
  double top = 0.0;
  for (const ToolPart& p : parts)
    if (!p.cutting) top = std::max(top, p.kind == ToolPart::Kind::Cylinder ? p.h1 : p.h0 + p.radius);
  const int slices = std::clamp(static_cast<int>(std::ceil(top_motion(pose_at, top) / kSliceMotion)), 1, kMaxSlices);
  std::vector<Depths> per(static_cast<size_t>(slices), Depths{});
  tbb::parallel_for(0, slices, [&](int k) {
    const double t0 = double(k) / slices, t1 = double(k + 1) / slices;
    BlockSweep cut, slice;
    sweep_block([&](double tau) { return pose_at(tau * t1); }, parts, opt_.sweep, cut, false, turn * t1);
    sweep_block([&](double tau) { return pose_at(t0 + tau * (t1 - t0)); }, parts, opt_.sweep, slice, false,
                turn * (t1 - t0));
    std::vector<Interval> removed, left;
    Depths& out = per[size_t(k)];
    auto interval = [&](const SweptPart& p, const Accum::Masked& m, Interval& iv) {
      const int u = Lattice::u_axis(m.d), v = Lattice::v_axis(m.d);
      Eigen::Vector3d o = lattice_.origin;
      o[u] += lattice_.h * m.iu;
      o[v] += lattice_.h * m.iv;
      if (o[u] < p.box.min()[u] || o[u] > p.box.max()[u] || o[v] < p.box.min()[v] || o[v] > p.box.max()[v]) return false;
      double a = 0.0, c = 0.0;
      if (!ray_interval(p, o, m.d, a, c)) return false;
      iv = {static_cast<float>(a), static_cast<float>(c)};
      return iv.hi > iv.lo;
    };
    for (const Accum& acc : accum_)
      for (const Accum::Masked& m : acc.masked) {
        removed.clear();
        Interval iv;
        for (const SweptPart& p : cut.parts)
          if (p.cutting && interval(p, m, iv)) removed.push_back(iv);
        merge_union(removed);
        subtract_intervals(acc.masked_pool.data() + m.offset, m.n, removed.data(), removed.size(), left, nullptr);
        if (left.empty()) continue;
        for (const SweptPart& p : slice.parts) {
          if (p.cutting || !interval(p, m, iv)) continue;
          double longest = 0.0;
          overlap_length(&iv, 1, left.data(), left.size(), &longest);
          float& slot = out[m.d][static_cast<int>(p.component)][static_cast<int>(HitWith::Stock)][0];
          slot = std::max(slot, static_cast<float>(longest));
        }
      }
  });
  for (const Depths& p : per)
    for (int d = 0; d < 3; ++d)
      for (int c = 0; c < 4; ++c) {
        float& slot = depth[d][c][static_cast<int>(HitWith::Stock)][0];
        slot = std::max(slot, p[d][c][static_cast<int>(HitWith::Stock)][0]);
      }
}

}  // namespace tf::sim
