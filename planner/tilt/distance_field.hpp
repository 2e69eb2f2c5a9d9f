// tiltfield planner (internal): a sparse, lazily built grid of exact distances to the check surfaces, used
// for the potential the tool body feels.
//
// The grid is split into bricks of kBrick^3 cells; a brick's (kBrick+1)^3 node values are exact
// point-to-triangle distances (TriangleBvh), clamped at `band`. A brick is computed on first use (or in
// parallel by prefetch) and bricks farther than `band` from every triangle store nothing. Between nodes
// the distance is interpolated trilinearly: continuous, and independent of the tessellation wherever the
// surface is flat (the node values are exact distances).
#pragma once
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <vector>

#include "clearance_bvh.hpp"

namespace tf {

class DistanceField {
 public:
  static constexpr int kBrick = 8;

  // cell: grid step, mm; band: distances at or beyond it are reported as `band`, mm.
  DistanceField(const ClearanceBvh& bvh, double cell, double band);

  double band() const { return band_; }
  double cell() const { return cell_; }

  // Distance at p (mm, <= band) and its gradient (unit-ish, zero in the far region). Builds the brick
  // under p when needed: not thread-safe. (Inline: the dynamics call it for every body point.)
  double sample(const Eigen::Vector3d& p, Eigen::Vector3d* gradient);

  // Builds, in parallel, every brick within `radius` of any of the points.
  void prefetch(const std::vector<Eigen::Vector3d>& points, double radius);

  size_t bricks_built() const { return built_; }
  size_t bricks_with_values() const { return values_.size() / kNodes; }

 private:
  static constexpr int kNodes = (kBrick + 1) * (kBrick + 1) * (kBrick + 1);
  static constexpr int32_t kUnbuilt = -1, kFar = -2;
  int64_t brick_id(int bx, int by, int bz) const { return (static_cast<int64_t>(bz) * dims_[1] + by) * dims_[0] + bx; }
  // Computes the node values of brick (bx, by, bz) into out (kNodes floats); returns false when the
  // brick is wholly farther than the band.
  bool compute_brick(int bx, int by, int bz, float* out) const;
  int32_t ensure(int bx, int by, int bz);

  const ClearanceBvh& bvh_;
  double cell_, band_;
  Eigen::Vector3d origin_;
  int dims_[3] = {0, 0, 0};       // bricks per axis
  std::vector<int32_t> index_;    // per brick: kUnbuilt, kFar or offset / kNodes into values_
  std::vector<float> values_;
  size_t built_ = 0;
};

inline double DistanceField::sample(const Eigen::Vector3d& p, Eigen::Vector3d* gradient) {
  if (gradient) gradient->setZero();
  if (index_.empty()) return band_;
  const Eigen::Vector3d g = (p - origin_) / cell_;
  // Outside the grid (checked in floating point, before any conversion to int): far from every surface.
  for (int k = 0; k < 3; ++k)
    if (!(g[k] >= 0.0 && g[k] < static_cast<double>(dims_[k]) * kBrick)) return band_;
  const int ix = static_cast<int>(std::floor(g.x())), iy = static_cast<int>(std::floor(g.y())),
            iz = static_cast<int>(std::floor(g.z()));
  const int bx = ix / kBrick, by = iy / kBrick, bz = iz / kBrick;
  if (ix < 0 || iy < 0 || iz < 0 || bx >= dims_[0] || by >= dims_[1] || bz >= dims_[2]) return band_;
  const int32_t id = index_[static_cast<size_t>(brick_id(bx, by, bz))];
  const int32_t b = id == kUnbuilt ? ensure(bx, by, bz) : id;
  if (b < 0) return band_;
  const float* v = values_.data() + static_cast<size_t>(b) * kNodes;
  const int lx = ix - bx * kBrick, ly = iy - by * kBrick, lz = iz - bz * kBrick;
  const double fx = g.x() - ix, fy = g.y() - iy, fz = g.z() - iz;
  constexpr int sy = kBrick + 1, sz = (kBrick + 1) * (kBrick + 1);
  const int base = lz * sz + ly * sy + lx;
  const double c000 = v[base], c100 = v[base + 1], c010 = v[base + sy], c110 = v[base + sy + 1];
  const double c001 = v[base + sz], c101 = v[base + sz + 1], c011 = v[base + sz + sy], c111 = v[base + sz + sy + 1];
  const double c00 = c000 + fx * (c100 - c000), c10 = c010 + fx * (c110 - c010);
  const double c01 = c001 + fx * (c101 - c001), c11 = c011 + fx * (c111 - c011);
  const double c0 = c00 + fy * (c10 - c00), c1 = c01 + fy * (c11 - c01);
  const double d = c0 + fz * (c1 - c0);
  if (gradient) {
    const double dx0 = (c100 - c000) + fy * ((c110 - c010) - (c100 - c000));
    const double dx1 = (c101 - c001) + fy * ((c111 - c011) - (c101 - c001));
    const double dy0 = c10 - c00, dy1 = c11 - c01;
    *gradient = Eigen::Vector3d(dx0 + fz * (dx1 - dx0), dy0 + fz * (dy1 - dy0), c1 - c0) / cell_;
  }
  return d;
}

}  // namespace tf
