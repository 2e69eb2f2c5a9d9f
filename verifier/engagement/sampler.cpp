// The engagement's point classification and sample grid (sampler.hpp).
#include "sampler.hpp"

#include <algorithm>

namespace tf::engagement {
namespace {

// Signed along-ray distance from coordinate t to the nearest material boundary of a ray (sorted, disjoint
// intervals): negative inside material, positive outside, +inf for no material.
[[gnu::always_inline]] inline double along_ray_distance(const Interval* b, const Interval* e, float t) {
  // The intervals are sorted and disjoint: the first one ending at or after t, and the one before it.
  const Interval* it = first_ending_after(b, e, t);
  if (it != e && t >= it->lo) return -std::min(t - it->lo, it->hi - t);
  double best = std::numeric_limits<double>::infinity();
  if (it != e) best = it->lo - t;
  if (it != b) best = std::min<double>(best, t - (it - 1)->hi);
  return best;
}

// Signed distance along ray (d, iu, iv) from coordinate t.
[[gnu::always_inline]] inline double ray_distance(const TriDexel& stock, int d, int iu, int iv, float t) {
  const Dexel& ray = stock.ray(d, iu, iv);
  return along_ray_distance(ray.begin(), ray.end(), t);
}

}  // namespace

double material_depth(const TriDexel& stock, const Eigen::Vector3d& p) {
  const Lattice& L = stock.lattice();
  const double inv_h = 1.0 / L.h;
  // The nearest lattice node along each axis: grid d's nearest ray is at the nodes of the other two.
  int k[3];
  for (int a = 0; a < 3; ++a) {
    // The range test comes first so that the conversion to int cannot overflow.
    const double f = (p[a] - L.origin[a]) * inv_h + 0.5;
    if (!(f >= 0.0 && f < L.n[a])) return std::numeric_limits<double>::infinity();  // outside: no material
    k[a] = static_cast<int>(f);
  }
  // Written out per grid (u = d + 1, v = d + 2 mod 3), so that the axes are constants.
  double best = ray_distance(stock, 0, k[1], k[2], static_cast<float>(p[0] - L.origin[0]));
  const double along_y = ray_distance(stock, 1, k[2], k[0], static_cast<float>(p[1] - L.origin[1]));
  if (std::abs(along_y) < std::abs(best)) best = along_y;
  const double along_z = ray_distance(stock, 2, k[0], k[1], static_cast<float>(p[2] - L.origin[2]));
  if (std::abs(along_z) < std::abs(best)) best = along_z;
  return best;
}

SampleGrid::SampleGrid(const Profile& prof, double spacing, const EngagementOptions& opt)
    : S(prof.length()), h(spacing) {
  na = std::max(8, static_cast<int>(std::lround(360.0 / std::max(0.01, opt.angle_step_deg))));
  dphi = 2.0 * kPi / na;
  const double ds_want = opt.axial_step_mm > 0 ? opt.axial_step_mm : std::max(h, prof.radius() * dphi);
  nr = std::clamp(static_cast<int>(std::ceil(S / ds_want)), 1, std::max(1, opt.max_rings));
  ds = S / nr;
  for (int i = 0; i < nr; ++i) {
    ring.push_back(prof.at(s_of(i)));
    below.push_back(prof.band_area(i * ds, s_of(i)));
    above.push_back(prof.band_area(s_of(i), (i + 1) * ds));
  }
  for (int i = 0; i + 1 < nr; ++i) {
    PairWeights w;
    static constexpr double kLinear[2] = {0, 1}, kLeft[3] = {-1, 0, 1}, kRight[3] = {0, 1, 2}, kCubic[4] = {-1, 0, 1, 2};
    prof.band_weights(s_of(i), s_of(i + 1), kLinear, 2, w.linear);
    prof.band_weights(s_of(i), s_of(i + 1), kLeft, 3, w.left);
    prof.band_weights(s_of(i), s_of(i + 1), kRight, 3, w.right);
    prof.band_weights(s_of(i), s_of(i + 1), kCubic, 4, w.cubic);
    weights.push_back(w);
    bool inside = false;
    for (const Profile::Joint& jt : prof.joints()) inside |= jt.s > s_of(i) && jt.s < s_of(i + 1);
    joint.push_back(inside ? 1 : 0);
  }
  for (int j = 0; j < na; ++j) {
    cos_phi.push_back(std::cos(phi_of(j)));
    sin_phi.push_back(std::sin(phi_of(j)));
  }
}

Sampler::Sampler(const TriDexel& stock, const ToolPose& before, const ToolPose& end, const Eigen::AlignedBox3d& region)
    : stock_(stock), region_(region) {
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
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(a, before.axis.normalized());
  before_ = frame_at(before, q * n);
}

RingFrame Sampler::ring(const ProfilePoint& pp) const {
  RingFrame f;
  f.c0 = end_.o + pp.z * end_.e3;
  f.a1 = pp.r * end_.e1;
  f.a2 = pp.r * end_.e2;
  f.dc = f.c0 - (before_.o + pp.z * before_.e3);
  f.d1 = pp.r * (end_.e1 - before_.e1);
  f.d2 = pp.r * (end_.e2 - before_.e2);
  f.n0 = pp.nz * end_.e3;
  f.n1 = pp.nr * end_.e1;
  f.n2 = pp.nr * end_.e2;
  return f;
}

}  // namespace tf::engagement
