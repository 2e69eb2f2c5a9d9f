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
#include <cstdint>
#include <vector>

#include "tiltfield/plan_bvh.hpp"

namespace tf {

class DistanceField {
 public:
  static constexpr int kBrick = 8;

  // cell: grid step, mm; band: distances at or beyond it are reported as `band`, mm.
  DistanceField(const ClearanceBvh& bvh, double cell, double band);

  double band() const { return band_; }
  double cell() const { return cell_; }

  // Distance at p (mm, <= band) and its gradient (unit-ish, zero in the far region). Builds the brick
  // under p when needed: not thread-safe.
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

}  // namespace tf
