// tiltfield engagement (internal): the state of a point of the cutting surface at a block's end, and the
// sample grid on the surface (rings along the profile, angles around the axis) with its tables.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "cutting_surface.hpp"
#include "tiltfield/dexel/tridexel.hpp"
#include "tiltfield/dexel/verify.hpp"
#include "tiltfield/engagement/engagement.hpp"

namespace tf::engagement {

// Signed distance along the deciding ray from p to the nearest material boundary (negative inside) in the
// stock before the block, by the nearest ray of each grid; the grid whose boundary is the closest decides
// (a ray crossing a boundary steeply places it exactly, one running along it is off by up to half a
// spacing, and loses). +inf outside the lattice.
double material_depth(const TriDexel& stock, const Eigen::Vector3d& p);

// How deep inside the tool a surface point's material test looks (mm): a block that only grazes a surface
// cut before (a repeated pass) engages nothing.
inline constexpr double kInside = 1e-3;

// A point faces its motion when nu . v / |v| exceeds this (a point moving along the surface does not cut).
inline constexpr double kMinFacing = 1e-6;

// A point of the cutting surface is engaged when it faces its own motion (facing > 0) and the stock held
// material an epsilon inside the tool there before the block (depth < 0). Both are continuous across the
// boundaries of the engaged region, so the refinement interpolates them. NaN where not evaluated.
struct PointState {
  bool engaged = false;
  float facing = std::numeric_limits<float>::quiet_NaN();  // nu . v / |v|
  float depth = std::numeric_limits<float>::quiet_NaN();   // material_depth just inside the tool, mm
};

// The sample grid on the cutting surface for one lattice spacing: nr rings at the middle of equal bands
// of the profile (arc length s_of(i)), na angles phi_of(j) around each, and the tables every block shares.
// The rings are about as far apart along the profile as the samples around the tool's rim (the area is
// integrated to second order between them), but not closer than the lattice spacing.
struct SampleGrid {
  SampleGrid(const Profile& prof, double spacing, const EngagementOptions& opt);
  double s_of(int i) const { return (i + 0.5) * ds; }
  double phi_of(int j) const { return (j + 0.5) * dphi; }
  int wrap(int j) const { return ((j % na) + na) % na; }

  double S, h;  // the profile's length and the lattice spacing, mm
  int nr = 0, na = 0;
  double ds = 0.0, dphi = 0.0;
  std::vector<ProfilePoint> ring;        // the rings' profile points
  // Per ring, the areas over the full turn (mm^2) of the profile from its band's lower edge i ds to the
  // ring, and from the ring to the upper edge (i + 1) ds.
  std::vector<double> below, above;
  // Per pair of neighbouring rings i, i + 1: the weights of the rings' engaged fractions in the area of
  // the band between them (Profile::band_weights) when the fraction is the polynomial through rings i and
  // i + 1 (linear), i - 1 to i + 1 or i to i + 2 (quadratic), or i - 1 to i + 2 (cubic); and whether a
  // joint of the profile lies between them.
  struct PairWeights {
    double linear[2], left[3], right[3], cubic[4];
  };
  std::vector<PairWeights> weights;
  std::vector<uint8_t> joint;
  std::vector<double> cos_phi, sin_phi;  // of phi_of(j)
};

// One ring of the cutting surface at the block's end, as functions of the angle's cosine c and sine s:
// the point x = c0 + c a1 + s a2, its motion over the last step v = dc + c d1 + s d2, its outward normal
// nu = n0 + c n1 + s n2. Made once per ring, so that a sample costs a few multiply-adds.
struct RingFrame {
  Eigen::Vector3d c0, a1, a2, dc, d1, d2, n0, n1, n2;
};

// Classifies points of the cutting surface at the block's end.
class Sampler {
 public:
  // `region`: where the material the block removed lies, grown by the classification's reach; points
  // outside it are not engaged without a look at the stock.
  Sampler(const TriDexel& stock, const ToolPose& before, const ToolPose& end, const Eigen::AlignedBox3d& region);
  RingFrame ring(const ProfilePoint& pp) const;
  // The point of ring f at the angle with cosine c and sine sn. Unless `measured`, a point that faces
  // away from its motion is only classified: its facing value (for the refinement) stays NaN.
  [[gnu::always_inline]] PointState state(const RingFrame& f, double c, double sn, bool measured = true) const {
    const Eigen::Vector3d x = f.c0 + c * f.a1 + sn * f.a2;
    if (!region_.contains(x)) return {};
    return classify(x, f.dc + c * f.d1 + sn * f.d2, f.n0 + c * f.n1 + sn * f.n2, measured);
  }
  // state(f, c, sn, false) for a point already found inside the region (mark_in_region's test, the same
  // arithmetic): the classification of a ring's marked samples, without testing the region twice.
  [[gnu::always_inline]] PointState state_in_region(const RingFrame& f, double c, double sn) const {
    return classify(f.c0 + c * f.a1 + sn * f.a2, f.dc + c * f.d1 + sn * f.d2, f.n0 + c * f.n1 + sn * f.n2, false);
  }
  // One column of the cutting surface (the angle with cosine c and sine sn, along the profile): the angle's
  // direction in the end frame and in the earlier one, so that a point of the column costs a few
  // multiply-adds (the meridian refinement walks columns).
  struct Column {
    Eigen::Vector3d dir, before_dir;
  };
  Column column(double c, double sn) const { return {c * end_.e1 + sn * end_.e2, c * before_.e1 + sn * before_.e2}; }
  // The point of column col at profile point pp, fully measured.
  PointState state(const Column& col, const ProfilePoint& pp) const {
    const Eigen::Vector3d x = end_.o + pp.r * col.dir + pp.z * end_.e3;
    if (!region_.contains(x)) return {};
    const Eigen::Vector3d earlier = before_.o + pp.r * col.before_dir + pp.z * before_.e3;
    return classify(x, x - earlier, pp.nr * col.dir + pp.nz * end_.e3, true);
  }
  const Eigen::AlignedBox3d& region() const { return region_; }
  const Frame& end_frame() const { return end_; }

 private:
  // A point x with motion v over the last step and outward normal nu (see PointState).
  [[gnu::always_inline]] PointState classify(const Eigen::Vector3d& x, const Eigen::Vector3d& v,
                                             const Eigen::Vector3d& nu, bool measured) const {
    PointState st;
    const double nv = nu.dot(v);
    if (!measured && nv <= 0.0) return st;  // faces away: the rear only rubs the wall it has cut
    const double vn = v.norm();
    if (!(vn > 1e-12)) return st;
    const double facing = nv / vn;
    st.facing = static_cast<float>(facing);
    if (facing <= kMinFacing) return st;
    const double depth = material_depth(stock_, x - kInside * nu);
    st.depth = static_cast<float>(depth);
    st.engaged = depth <= 0.0;
    return st;
  }

  const TriDexel& stock_;
  Eigen::AlignedBox3d region_;
  Frame end_, before_;
};

// The boundary between two points of opposite states, as a parameter t in (0, 1) from the first to the
// second: state(t) is evaluated at most `evaluations` times, each at the zero of the measure that tells the
// two apart (facing where the non-engaged end turns away, depth where it lies outside the material),
// kept inside the bracket's middle 80 %; where neither says, or where the same end moved twice in a row
// (the measure jumps there, as facing does at a kink of the profile), at the bracket's middle. Stops when
// the bracket is below `width` (in t) and returns the zero of the final bracket.
template <class State>
double refine_boundary(PointState a, PointState b, double width, int evaluations, const State& state) {
  double lo = 0.0, hi = 1.0;
  auto zero = [&](double t0, const PointState& s0, double t1, const PointState& s1) {
    const PointState& off = s0.engaged ? s1 : s0;
    double f0 = NAN, f1 = NAN;
    if (off.facing <= kMinFacing) {
      f0 = s0.facing - kMinFacing, f1 = s1.facing - kMinFacing;
    } else if (off.depth > 0.0f && std::isfinite(off.depth)) {
      f0 = -s0.depth, f1 = -s1.depth;
    }
    const double f = f0 / (f0 - f1);
    return std::isfinite(f) && f >= 0.0 && f <= 1.0 ? t0 + (t1 - t0) * f : 0.5 * (t0 + t1);
  };
  int moved = 0, repeats = 0;  // the end moved last (-1 lo, +1 hi) and how often in a row
  for (int k = 0; k < evaluations && hi - lo > width; ++k) {
    const double span = hi - lo;
    const double t = repeats >= 2 ? lo + 0.5 * span : std::clamp(zero(lo, a, hi, b), lo + 0.1 * span, hi - 0.1 * span);
    const PointState s = state(t);
    const int side = s.engaged == a.engaged ? -1 : 1;
    repeats = side == moved ? repeats + 1 : 1;
    moved = side;
    if (repeats > 2) repeats = 1;  // after a halving, interpolation again
    if (side < 0) {
      lo = t;
      a = s;
    } else {
      hi = t;
      b = s;
    }
  }
  return zero(lo, a, hi, b);
}

}  // namespace tf::engagement
